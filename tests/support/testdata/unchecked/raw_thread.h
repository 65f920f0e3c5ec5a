// A module that starts its body the unchecked way; unchecked_threads.sh must find it.
struct RawThread : sc_core::sc_module {
    SC_HAS_PROCESS(RawThread);
    explicit RawThread(sc_core::sc_module_name n) : sc_module(n) { SC_THREAD(run); }
    void run() {}
};
