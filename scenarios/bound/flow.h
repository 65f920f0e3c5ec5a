// rcsim — the control flow of a ROM from one entry, read from its bytes (scenarios/bound/bound.h).
//
// The graph has one node per instruction per call site: every CALL is inlined (its callee's
// instructions get a context of their own, so a RET goes back to the one call site it came
// from and a value the caller set reaches the callee). Along the edges flows what the code states
// about itself: intervals of the general registers (a MOV of a constant, AND with a mask, a
// compare before a conditional jump, JCXZ), the words pushed on the stack (so POP and POPF give
// back what PUSH and PUSHF saved), IF, and whether the source's EOI was written. That is enough to
// bound LOOP and REP counts from CX, counters from their start, and to read jump tables.
#pragma once

#include "comm_cpu/i8086/disasm.h"
#include "scenarios/bound/bound.h"

#include <cstdint>
#include <map>
#include <string>
#include <tuple>
#include <vector>

namespace rcsim::bound {

/// An unsigned interval of a 16-bit register; `even` when the value is known to be even.
struct Interval {
    std::uint32_t lo = 0, hi = 0xFFFF;
    bool even = false;
    static Interval top() { return {}; }
    static Interval constant(std::uint32_t v) { return {v & 0xFFFF, v & 0xFFFF, (v & 1) == 0}; }
    bool is_constant() const { return lo == hi; }
    bool operator==(const Interval& o) const { return lo == o.lo && hi == o.hi && even == o.even; }
};

/// IF as far as the code states it. `startup`: interrupts not enabled yet since the reset.
enum class IfState : std::uint8_t { off, on, unknown, startup };
/// The source's EOI: not yet written, written, or written on some paths only.
enum class Eoi : std::uint8_t { no, yes, maybe };

/// A word on the abstract stack: a value, or the FLAGS image a PUSHF saved (its IF).
struct StackWord {
    Interval value;
    bool flags = false;
    IfState if_saved = IfState::unknown;
    int bp_depth = -1; // PUSH BP: the frame base depth BP stood for, which POP BP gives back
    int writer[2] = {-1, -1}; // PUSH r: who last wrote r's low and high byte (or the word)
    bool operator==(const StackWord& o) const {
        return value == o.value && flags == o.flags && if_saved == o.if_saved && bp_depth == o.bp_depth &&
               writer[0] == o.writer[0] && writer[1] == o.writer[1];
    }
};

struct State {
    Interval reg[8];                  // AX CX DX BX SP BP SI DI (SP's interval unused)
    // The byte registers AL CL DL BL AH CH DH BH, kept beside their words: a byte's range is
    // often known when its word's is not (XOR AH,AH after a compare of AL).
    Interval b8[8] = {{0, 0xFF}, {0, 0xFF}, {0, 0xFF}, {0, 0xFF}, {0, 0xFF}, {0, 0xFF}, {0, 0xFF}, {0, 0xFF}};
    IfState if_flag = IfState::off;
    Eoi eoi = Eoi::no;
    std::vector<StackWord> stack;     // the newest word last
    bool half_popped = false;         // an INC SP without its pair yet
    std::vector<IfState> saved_if;    // irq_save ... irq_restore (annotations)
    // A register holding a FLAGS image (PUSHF; POP r): the IF it saved, until the register changes.
    IfState reg_flags[8] = {IfState::unknown, IfState::unknown, IfState::unknown, IfState::unknown,
                            IfState::unknown, IfState::unknown, IfState::unknown, IfState::unknown};
    bool reg_is_flags[8] = {};
    int bp_depth = -1;                // the stack depth a MOV BP,SP recorded (-1: none)
    // The last CMP reg,imm whose flags are still current: reg index (byte regs 8..15: AL..BH), value.
    int cmp_reg = -1;
    std::uint32_t cmp_value = 0;
    bool cmp_zero_only = false;       // INC/DEC/OR r,r: ZF tells r = 0, CF tells nothing
    // Which node last wrote each register (AL CL DL BL AH CH DH BH, then SP BP SI DI): -1 before
    // the entry, kMixed where paths with different writers meet. POP gives back the writer of
    // the value it restores, so a counter saved and restored around a call keeps its writer.
    static constexpr int kMixed = -2;
    int writer[12] = {-1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
    int now = -1;                     // the node being executed (the writer it records)
    bool operator==(const State& o) const;
};

/// One decoded instruction of the ROM.
struct Insn {
    std::uint32_t address = 0; // linear
    std::uint16_t ip = 0;   // the offset of its first decoding (the low 4 bits are what timing needs)
    std::uint8_t bytes[16] = {};
    unsigned length = 0;
    unsigned prefixes = 0;
    std::uint8_t opcode = 0;
    bool rep = false;
    int segment = -1;       // an override prefix: 0 ES, 1 CS, 2 SS, 3 DS
    // ModR/M, when the opcode has one
    bool has_modrm = false;
    unsigned mod = 0, reg = 0, rm = 0;
    std::int32_t disp = 0;
    std::uint32_t imm = 0;  // the immediate, when there is one
    i8086::Flow flow = i8086::Flow::next;
    std::string text;       // the mnemonic
};

struct Node {
    std::uint32_t address = 0;
    std::uint16_t cs = 0, ip = 0;
    int context = 0;
    const Insn* insn = nullptr;
    State in;
    unsigned updates = 0;
    struct Edge {
        int to;
    };
    std::vector<Edge> out;
    bool exit = false; // IRET of the entry's context (or HLT): a path ends here
};

/// A call site's context: the caller's context, where the call returns, which routine runs.
struct Context {
    int parent = -1;
    std::uint32_t call_site = 0;
    std::uint16_t return_cs = 0, return_ip = 0;
    std::uint32_t routine = 0;
    bool restores_if = false; // the routine is annotated irq_restore
    bool saves_if = false;    // ... irq_save
    unsigned stack_at_call = 0; // abstract stack depth before the CALL pushed its return address
};

/// The graph of every instruction reachable from one entry.
class FlowGraph {
public:
    FlowGraph(const Inputs& inputs, std::uint16_t cs, std::uint16_t ip, State entry_state, std::string entry_name);
    const std::vector<Node>& nodes() const { return nodes_; }
    const Context& context(int c) const { return contexts_[std::size_t(c)]; }
    /// The state after `n` along its edge to `to` (the edge's refinements applied).
    State out_state(int n, int to) const;
    /// Whether the instruction writes the 16-bit register r (0..7) or a byte of it.
    static bool writes(const Insn& insn, int r);
    /// The byte register (AL..BH) an instruction writes when that byte is all it writes of its
    /// word, else -1.
    static int writes_byte_only(const Insn& insn);
    /// The symbolised address: SYMBOL+0xOFF, else 0xADDRESS.
    std::string where(std::uint32_t address) const;
    const Insn& insn_at(std::uint32_t address, std::uint16_t ip) const;
    const Inputs& inputs() const { return in_; }
    const Annotation* annotation(std::uint32_t address, Annotation::Kind kind) const;

private:
    int node_for(int context, std::uint16_t cs, std::uint16_t ip);
    void build(State entry_state);
    void successors(int n, std::vector<std::pair<int, State>>& out);
    std::vector<std::uint16_t> indirect_targets(int n);
    int call_context(int from, std::uint32_t routine, std::uint16_t ret_cs, std::uint16_t ret_ip, unsigned depth);
    [[noreturn]] void fail(std::uint32_t address, const std::string& why) const;

    const Inputs& in_;
    std::string entry_name_;
    std::vector<Node> nodes_;
    std::vector<Context> contexts_;
    std::map<std::pair<int, std::uint32_t>, int> index_;       // (context, address) -> node
    std::map<std::pair<int, std::uint32_t>, int> context_of_;  // (parent, call site) -> context
    mutable std::map<std::uint32_t, Insn> insns_; // by linear address
};

} // namespace rcsim::bound
