// A bench that starts its body the unchecked way; unchecked_threads.sh must find it.
struct Bench : sc_core::sc_module {
    SC_HAS_PROCESS(Bench);
    explicit Bench(sc_core::sc_module_name n) : sc_module(n) { SC_THREAD(run); }
    void run() {}
};
