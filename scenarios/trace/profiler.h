// rcsim — the cycle profiler of the communication CPU (`rcsim run --profile`; docs/tools.md
// "Profiler").
//
// It needs no firmware cooperation: it watches the 8086 core at every instruction boundary
// (i8086::StepHook: CS:IP, SS:SP and the clock count before each instruction) and every bus cycle
// (the two INTA cycles of a hardware interrupt), and keeps a shadow call stack:
//   - a CALL (E8, 9A, FF /2, FF /3) whose push is seen (SP down by 2 or 4 at the next boundary)
//     opens a frame for the function at the target; INT n likewise (SP down by 6);
//   - RET/RETF/IRET close every frame whose return address the instruction popped (the frames
//     whose entry SP is now below SP: a longjmp-like unwinding closes them too);
//   - INTA cycles open an interrupt frame at the handler, in the context of its IR level. The
//     clocks from the first INTA's T1 to the handler's first instruction (the 8086's interrupt
//     sequence: INTA cycles, vector fetch, three pushes) are the handler's.
// Each instruction's clocks (boundary to boundary) are the self clocks of the innermost frame; the
// idle clocks after a HLT are the halting function's until the interrupt that ends them.
//
// Per function and context (main program, IRn, IRn nested = entered while another ISR ran):
// completed calls, self clocks, inclusive clocks (self + callees, without the interrupts that
// came in meanwhile: they are counted in their own context) and min/mean/max inclusive clocks per
// call. A recursive function's inclusive clocks count its outermost activation once.
//
// Functions are named by `name_of` (a symbol table's containing(); scenarios/debug/symbols.h) when
// a frame opens, so the per-instruction work is a few compares. Memory: one node per distinct call
// path (bounded for firmware without unbounded recursion) and one frame per active call.
//
// Plain C++ (no SystemC).
#pragma once

#include "comm_cpu/i8086/cpu.h"

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

namespace rcsim::trace {

class CycleProfiler {
public:
    /// The name of the function holding a linear address.
    using NameOf = std::function<std::string(std::uint32_t linear)>;
    explicit CycleProfiler(NameOf name_of);

    // ---- the feeds ----
    /// At each instruction boundary, before the instruction at cpu.pc() executes.
    void step(const i8086::Cpu& cpu);
    /// Every bus cycle (INTA opens an interrupt frame at the next boundary).
    void bus(const i8086::BusRecord& r);
    /// The end of the run at cycle `end`: the clocks since the last boundary are the innermost
    /// frame's; frames still open add their inclusive clocks but count no completed call.
    void finish(i8086::cycles_t end);

    // ---- the results ----
    struct Row {
        std::string function, context;
        std::uint64_t calls = 0;       // completed
        std::uint64_t self = 0, inclusive = 0;
        std::uint64_t min = 0, max = 0; // inclusive clocks of one completed call
        double mean = 0;
    };
    /// Every (function, context) that ran, by self clocks (largest first), then name and context.
    std::vector<Row> rows() const;
    /// Every clock from the first boundary to finish() is some frame's self clock.
    std::uint64_t total_clocks() const { return total_; }

    /// The call tree: node 0 the root, its children the contexts ("main", "IR0", ...), theirs
    /// the functions. self = clocks spent in the node's function on that path.
    struct Node {
        std::string name;
        std::uint64_t self = 0;
        std::map<std::string, unsigned> children; // by name: output in name order
    };
    const std::vector<Node>& tree() const { return tree_; }
    /// self + the children's totals.
    std::uint64_t total_of(unsigned node) const;

    /// profile.txt: the sorted table, clocks and microseconds at `clock_hz`.
    void write_table(std::ostream& os, double clock_hz) const;
    /// profile.folded: "context;f;g clocks" per call path with self clocks (flamegraph.pl,
    /// speedscope), paths in name order.
    void write_folded(std::ostream& os) const;

private:
    enum class Transfer : std::uint8_t { none, call_near, call_far, int_sw, ret };
    struct Stat {
        std::uint64_t calls = 0, self = 0, inclusive = 0, min = ~std::uint64_t(0), max = 0, sum = 0;
        unsigned active = 0; // activations on the stack (recursion)
    };
    struct Frame {
        unsigned stat, node;
        unsigned context;
        i8086::cycles_t entry = 0, interrupted = 0; // interrupted: clocks of ISRs that came in
        std::uint32_t sp = 0;                       // linear SS:SP at the first instruction
        bool isr = false;
    };

    NameOf name_of_;
    std::vector<std::string> functions_;                   // by id
    std::unordered_map<std::uint32_t, unsigned> fn_at_;    // entry address -> function id
    std::vector<std::string> contexts_;                    // by id
    std::map<std::pair<unsigned, unsigned>, unsigned> stat_of_; // (function, context) -> stat
    std::vector<Stat> stats_;
    std::vector<Node> tree_;
    std::vector<Frame> frames_;

    bool started_ = false;
    i8086::cycles_t last_ = 0;
    std::uint64_t total_ = 0;
    Transfer prev_ = Transfer::none; // what the instruction at the last boundary does
    std::uint32_t prev_sp_ = 0;
    unsigned intas_ = 0;             // INTA cycles since the last boundary
    i8086::cycles_t inta_start_ = 0;
    unsigned inta_vector_ = 0;

    unsigned function_at(std::uint32_t linear);
    unsigned context_id(const std::string& name);
    unsigned child(unsigned node, const std::string& name);
    void charge(i8086::cycles_t clocks);
    void open(std::uint32_t target, std::uint32_t sp, unsigned context, unsigned parent_node, i8086::cycles_t at,
              bool isr);
    void close(i8086::cycles_t at, bool completed);
    static Transfer decode(const i8086::Cpu& cpu);
};

} // namespace rcsim::trace
