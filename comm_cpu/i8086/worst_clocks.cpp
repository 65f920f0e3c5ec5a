// rcsim — the worst-case clocks of one 8086 instruction, measured on the core. See worst_clocks.h.
//
// Each measurement is one run on a private Cpu whose every bus cycle goes through the harness
// below (no memory map), as in the SingleStepTests set-up (sst.cpp): code fetches answer by
// address a preamble's bytes (while it runs), the instruction's (or a sequence's pieces' at their
// addresses) and NOPs everywhere else; data reads a fill
// pattern (or what a run wrote); I/O reads and INTA a fixed value. Every cycle gets the wait
// states WaitBounds gives its kind. A run is (preamble, register set-up, fill pattern); the
// worst over runs is the bound. Two stages keep the count modest: every set-up (alignment,
// operand values, flags, counts) from a few BIU states, then the set-ups that came within a
// bus cycle of the worst from every BIU state the preambles make.
#include "comm_cpu/i8086/worst_clocks.h"

#include "comm_cpu/i8086/disasm.h"
#include "comm_cpu/i8086/worst_clocks_setups.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace rcsim::i8086 {

using worst_setups::alignments;
using worst_setups::muldiv_values;
using worst_setups::Values;

namespace {

constexpr std::uint8_t kNop = 0x90;
constexpr std::uint16_t kCs = 0x4000, kDs = 0x1000, kSs = 0x2000, kEs = 0x3000;
constexpr std::uint8_t kIntaVector = 0x08; // what the INTA cycles answer: an 8259A's IR0 type
/// All six status flags set (CF, PF, AF, ZF, SF, OF); IF and TF stay clear in instruction runs.
constexpr std::uint16_t kAllStatus = 0x08D5;

/// The memory a run sees where it did not write: a constant byte (0xFF: every pointer read
/// from memory odd, 0x00: even) or, for CMPS/SCAS, bytes counting 80h..FFh in the order they
/// are read, so that no two compared bytes are equal and none equals 33h: a REPNE run never
/// finds its byte.
enum class Fill : std::uint8_t { ones, zeros, counting };

/// One register set-up of the instruction (CS and IP come from the measurement).
struct Setup {
    Registers regs;
    Fill fill = Fill::ones;
    bool operand = false;        // the first data read (a MUL/DIV memory operand) answers `value`
    bool word = false;           // ... a word (else a byte)
    std::uint16_t value = 0;
};

/// A preamble: instructions stepped through before the target to leave the queue and the BIU
/// in another state at its boundary, or (queue > 0) the target's first bytes already queued.
struct Preamble {
    std::vector<std::uint8_t> bytes;
    unsigned instructions = 0;
    unsigned queue = 0;
    bool halt = false; // (interrupt entry) ends halted
};

// Preamble instructions that change no register the target's set-up needs (the set-up is
// written at the target's boundary anyway): NOP (1 byte, 3 clocks), CLC (1 byte, 2 clocks),
// MOV AL,AL (2 bytes, 2 clocks: drains the queue), MUL CL (slow: the queue fills), MOV [BX],AL
// (a data write holds the bus), JMP $+2 (flushes the queue: the target right after a jump),
// CALL $+3 (the same after the return address's write: a called function's first instruction).
const std::uint8_t kPNop[] = {0x90}, kPClc[] = {0xF8}, kPMov[] = {0x88, 0xC0}, kPMul[] = {0xF6, 0xE1},
                   kPWrite[] = {0x88, 0x07}, kPJmp[] = {0xEB, 0x00}, kPCall[] = {0xE8, 0x00, 0x00};

void add(Preamble& p, const std::uint8_t* b, unsigned n, unsigned times = 1) {
    for (unsigned t = 0; t < times; ++t) {
        p.bytes.insert(p.bytes.end(), b, b + n);
        ++p.instructions;
    }
}

std::vector<Preamble> all_preambles() {
    std::vector<Preamble> out;
    out.push_back({});
    for (unsigned q = 1; q <= 6; ++q) out.push_back(Preamble{{}, 0, q, false});
    for (unsigned k = 1; k <= 6; ++k) {
        Preamble a, b;
        add(a, kPNop, 1, k);
        add(b, kPClc, 1, k);
        out.push_back(a);
        out.push_back(b);
    }
    for (unsigned k = 1; k <= 3; ++k) {
        Preamble p;
        add(p, kPMov, 2, k);
        out.push_back(p);
    }
    const std::pair<const std::uint8_t*, unsigned> heads[] = {{kPMul, 2}, {kPWrite, 2}, {kPJmp, 2}, {kPCall, 3}};
    for (const auto& [head, n] : heads) {
        for (unsigned k = 0; k <= 3; ++k) {
            Preamble a, b;
            add(a, head, n);
            add(b, head, n);
            add(a, kPNop, 1, k);
            add(b, kPClc, 1, k);
            out.push_back(a);
            if (k) out.push_back(b);
        }
        Preamble m;
        add(m, head, n);
        add(m, kPMov, 2);
        out.push_back(m);
    }
    return out;
}

/// The few BIU states every set-up is tried from first: empty queue, full queue, after NOPs.
std::vector<Preamble> first_preambles() {
    std::vector<Preamble> out;
    out.push_back({});
    out.push_back(Preamble{{}, 0, 6, false});
    Preamble p;
    add(p, kPNop, 1, 2);
    out.push_back(p);
    return out;
}

/// The REP count above which set-ups and BIU states are chosen with this many elements.
constexpr std::uint16_t kRepProbe = 64;

/// Set-ups taken to stage 2 (at most two with the same stage-1 time).
constexpr std::size_t kChosen = 6;

bool is_string(std::uint8_t op) { return (op >= 0xA4 && op <= 0xA7) || (op >= 0xAA && op <= 0xAF); }

std::uint32_t linear(std::uint16_t cs, std::uint16_t ip) { return ((std::uint32_t(cs) << 4) + ip) & 0xFFFFF; }

/// Code bytes at cs:ip onwards (offsets wrap within the segment).
struct Run {
    std::uint16_t cs = 0, ip = 0;
    std::vector<std::uint8_t> bytes;
    /// Whether this run holds linear address `a`; its byte in `b`.
    bool at(std::uint32_t a, std::uint8_t& b) const {
        const std::uint32_t off = (a - (std::uint32_t(cs) << 4)) & 0xFFFFF;
        if (off > 0xFFFF) return false;
        const std::uint16_t i = std::uint16_t(off - ip);
        if (i >= bytes.size()) return false;
        b = bytes[i];
        return true;
    }
};

} // namespace

/// What a measurement runs after its preamble: `steps` instructions from `ip` in segment kCs.
struct WorstClocks::Code {
    std::vector<Run> runs;           // the pieces, in flow order
    std::vector<std::uint8_t> first; // the first piece's bytes (its form chooses the set-ups)
    std::uint16_t ip = 0;            // the first piece's
    unsigned steps = 1;
    bool strings = false;            // a string instruction among the pieces
    std::uint8_t branch = 0;         // the last piece's opcode when it is a conditional transfer (branch())
    // branch(): the status flags and CX written at the last piece's boundary to force its outcome
    bool forced = false;
    std::uint16_t force_flags = 0, force_cx = 0;
};

struct WorstClocks::Harness : BusHandler {
    WaitBounds waits;
    Cpu cpu;
    const Code* code = nullptr;
    Run preamble;            // answers its addresses while the preamble runs (then the pieces')
    bool in_preamble = false;
    Fill fill = Fill::ones;
    // RAM a run wrote: a byte is valid when its stamp is the run's
    std::vector<std::uint8_t> ram = std::vector<std::uint8_t>(1u << 20);
    std::vector<std::uint32_t> stamp = std::vector<std::uint32_t>(1u << 20);
    std::uint32_t run = 1;
    unsigned operand_bytes = 0, operand_left = 0; // the next data bytes read answer `value` (low first)
    std::uint16_t value = 0;
    bool vector0 = false; // a read of 00000-00003: the divide error's vector
    std::uint8_t counter = 0; // Fill::counting's next byte

    explicit Harness(const WaitBounds& w) : waits(w) { cpu.set_bus_handler(this); }

    std::uint8_t code_byte(std::uint32_t a) const {
        std::uint8_t b = kNop;
        if (in_preamble && preamble.at(a, b)) return b;
        for (const Run& r : code->runs)
            if (r.at(a, b)) return b;
        return kNop;
    }

    std::uint8_t read_byte(std::uint32_t a) {
        a &= 0xFFFFF;
        if (a < 4) vector0 = true;
        if (operand_left) {
            const unsigned i = operand_bytes - operand_left--;
            return std::uint8_t(value >> (8 * i));
        }
        if (stamp[a] == run) return ram[a];
        switch (fill) {
        case Fill::ones: return 0xFF;
        case Fill::zeros: return 0x00;
        case Fill::counting: return std::uint8_t(0x80 | counter++);
        }
        return 0;
    }

    unsigned bus_access(Bus kind, std::uint32_t address, std::uint16_t& data, unsigned width, cycles_t) override {
        switch (kind) {
        case Bus::code_fetch: {
            const std::uint8_t lo = code_byte(address & 0xFFFFF);
            data = width == 2 ? std::uint16_t(lo | (code_byte((address + 1) & 0xFFFFF) << 8)) : lo;
            return waits.code;
        }
        case Bus::mem_read: {
            const std::uint8_t lo = read_byte(address);
            data = width == 2 ? std::uint16_t(lo | (read_byte(address + 1) << 8)) : lo;
            return waits.data;
        }
        case Bus::mem_write:
            for (unsigned i = 0; i < width; ++i) {
                const std::uint32_t a = (address + i) & 0xFFFFF;
                ram[a] = std::uint8_t(data >> (8 * i));
                stamp[a] = run;
            }
            return waits.data;
        case Bus::io_read: data = 0xFFFF; return waits.io;
        case Bus::io_write: return waits.io;
        case Bus::int_ack: data = kIntaVector; return waits.inta;
        default: return 0;
        }
    }

    /// One run: the preamble, then the set-up written at the target's boundary, then the
    /// target's step()s. `fault`: a read of the divide error's vector, when the target can raise it.
    unsigned measure(const Code& target, const Preamble& p, const Setup& s, bool can_fault, bool& fault) {
        begin(p, target);
        Registers& r = cpu.regs();
        for (int i = 0; i < 8; ++i) r.r[i] = s.regs.r[i];
        r.flags = std::uint16_t((s.regs.flags & 0x0CD5) | 0xF002); // (never IF or TF)
        fill = s.fill;
        value = s.value;
        operand_bytes = operand_left = s.operand ? (s.word ? 2 : 1) : 0;
        vector0 = false;
        const cycles_t c0 = cpu.cycles();
        for (unsigned i = 0; i < target.steps; ++i) {
            // (a POPF of the fill sets TF, which the firmware never does: no single-step trap)
            cpu.regs().flags &= std::uint16_t(~flag::TF);
            if (target.forced && i + 1 == target.steps) {
                Registers& f = cpu.regs();
                f.flags = std::uint16_t((f.flags & ~kAllStatus) | target.force_flags);
                f.r[CX] = target.force_cx;
            }
            cpu.step();
        }
        fault = can_fault && vector0;
        return unsigned(cpu.cycles() - c0);
    }

    /// Puts the CPU before the preamble, which runs into the target at its `ip`.
    void begin(const Preamble& p, const Code& target) {
        ++run;
        vector0 = false;
        operand_left = 0;
        code = &target;
        const std::uint16_t ip = target.ip;
        preamble = Run{kCs, std::uint16_t(ip - p.bytes.size()), p.bytes};
        in_preamble = true;
        Registers r;
        r.s[CS] = kCs;
        r.s[DS] = kDs;
        r.s[SS] = kSs;
        r.s[ES] = kEs;
        r.r[SP] = 0x8000;
        r.r[BX] = 0x0100;
        r.ip = preamble.ip;
        std::array<std::uint8_t, 6> q{};
        for (unsigned i = 0; i < p.queue; ++i) q[i] = code_byte(linear(kCs, std::uint16_t(r.ip + i)));
        cpu.load_state(r, q.data(), p.queue);
        cpu.start();
        for (unsigned i = 0; i < p.instructions; ++i) cpu.step();
        if (p.halt) {
            cpu.step(); // the HLT
            cpu.step(); // an idle clock in the halt
        }
        in_preamble = false;
    }
};

WorstClocks::WorstClocks(const WaitBounds& waits) : waits_(waits), harness_(std::make_unique<Harness>(waits)) {}
WorstClocks::~WorstClocks() = default;

unsigned WorstClocks::instruction(const std::uint8_t* bytes, unsigned length, std::uint16_t ip, std::uint32_t cx_max) {
    const std::vector<std::uint8_t> b(bytes, bytes + length);
    std::string key(b.begin(), b.end());
    key += char(ip & 1);
    key += std::to_string(cx_max);
    const auto it = cache_.find(key);
    if (it != cache_.end()) return it->second;
    Code code;
    code.runs.push_back(Run{kCs, ip, b});
    code.first = b;
    code.ip = ip;
    code.strings = is_string(decode(b.data(), length).opcode);
    const unsigned c = measure(code, cx_max);
    cache_.emplace(std::move(key), c);
    return c;
}

namespace {

/// Why sequence() cannot take the instruction `d` at `b`, or nullptr.
const char* excluded(const std::uint8_t* b, const Decoded& d, std::uint16_t ip) {
    const std::uint8_t op = d.opcode;
    const unsigned reg = d.prefixes + 1 < d.length ? (b[d.prefixes + 1] >> 3) & 7 : 0;
    bool rep = false;
    for (unsigned i = 0; i < d.prefixes; ++i) rep = rep || b[i] == 0xF2 || b[i] == 0xF3;
    switch (d.flow) {
    case Flow::branch: return "a conditional transfer";
    case Flow::ret_near:
    case Flow::ret_far:
    case Flow::iret: return "a return";
    case Flow::int_sw: return "a software interrupt";
    case Flow::halt: return "HLT";
    case Flow::jump:
    case Flow::jump_far:
    case Flow::call_near:
    case Flow::call_far:
        if (!direct_target(b, d, ip)) return "a transfer through a register or memory";
        break;
    case Flow::next: break;
    }
    if (rep && is_string(op)) return "a REP string instruction";
    if (op == 0xD2 || op == 0xD3) return "a shift or rotate by CL";
    if ((op == 0xF6 || op == 0xF7) && reg >= 4) return "MUL, IMUL, DIV or IDIV";
    if (op == 0xD4 || op == 0xD5) return "AAM or AAD";
    return nullptr;
}

[[noreturn]] void reject(bool branch, std::size_t i, std::uint16_t ip, const std::string& why) {
    char where[64];
    std::snprintf(where, sizeof where, "WorstClocks::%s: piece %zu (IP %04X): ", branch ? "branch" : "sequence", i,
                  unsigned(ip));
    throw std::invalid_argument(where + why);
}

/// Whether the conditional transfer `op` (70-7F and the aliases 60-6F, E0-E3) is taken with the
/// status flags `f` and CX = `cx` before it (the iAPX 86/88 User's Manual: LOOP* decrement CX
/// first and test the result; JCXZ tests CX as it is).
bool taken(std::uint8_t op, std::uint16_t f, std::uint16_t cx) {
    const bool cf = f & flag::CF, pf = f & flag::PF, zf = f & flag::ZF, sf = f & flag::SF, of = f & flag::OF;
    const bool counted = cx != 1; // CX - 1 != 0
    switch (op) {
    case 0xE0: return counted && !zf; // LOOPNE
    case 0xE1: return counted && zf;  // LOOPE
    case 0xE2: return counted;        // LOOP
    case 0xE3: return cx == 0;        // JCXZ
    default: break;
    }
    bool c = false;
    switch ((op >> 1) & 7) {
    case 0: c = of; break;              // JO / JNO
    case 1: c = cf; break;              // JB / JNB
    case 2: c = zf; break;              // JZ / JNZ
    case 3: c = cf || zf; break;        // JBE / JA
    case 4: c = sf; break;              // JS / JNS
    case 5: c = pf; break;              // JP / JNP
    case 6: c = sf != of; break;        // JL / JGE
    case 7: c = zf || sf != of; break;  // JLE / JG
    }
    return (op & 1) ? !c : c;
}

} // namespace

bool WorstClocks::sequenceable(const std::uint8_t* bytes, unsigned length, std::uint16_t ip) {
    const Decoded d = bytes ? decode(bytes, length) : Decoded{};
    return d.length && !excluded(bytes, d, ip);
}

WorstClocks::Code WorstClocks::lay_out(const std::vector<Piece>& pieces, bool branch, std::string& key) const {
    if (pieces.empty()) throw std::invalid_argument(branch ? "WorstClocks::branch: no pieces" : "WorstClocks::sequence: no pieces");
    Code code;
    std::uint16_t cs = kCs, next = pieces[0].ip; // where the flow goes
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        const Piece& p = pieces[i];
        const bool last = i + 1 == pieces.size();
        const Decoded d = p.bytes ? decode(p.bytes, p.length) : Decoded{};
        if (d.length == 0) reject(branch, i, p.ip, "its bytes end inside the instruction");
        const bool ret = d.flow == Flow::ret_near || d.flow == Flow::ret_far || d.flow == Flow::iret;
        if (branch && last && d.flow != Flow::branch) reject(branch, i, p.ip, "the last piece is not a conditional transfer");
        if (!(last && (branch ? d.flow == Flow::branch : ret)))
            if (const char* why = excluded(p.bytes, d, p.ip))
                reject(branch, i, p.ip,
                       why + std::string(ret || d.flow == Flow::branch ? " can only end a line" : " keeps its own bound"));
        if (p.ip != next) {
            char was[48];
            std::snprintf(was, sizeof was, "the previous piece goes to IP %04X", unsigned(next));
            reject(branch, i, p.ip, was);
        }
        Run run{cs, p.ip, std::vector<std::uint8_t>(p.bytes, p.bytes + d.length)};
        for (std::uint16_t j = 0; j < d.length; ++j)
            for (const Run& r : code.runs) {
                std::uint8_t b = 0;
                if (r.at(linear(cs, std::uint16_t(p.ip + j)), b) && b != run.bytes[j])
                    reject(branch, i, p.ip, "another piece holds other bytes at its address");
            }
        key.append(run.bytes.begin(), run.bytes.end());
        key += char(p.ip & 1);
        code.strings = code.strings || is_string(d.opcode);
        code.runs.push_back(std::move(run));
        next = std::uint16_t(p.ip + d.length);
        if (d.flow == Flow::branch) code.branch = d.opcode;
        else if (d.flow != Flow::next && !ret) { // (a direct JMP or CALL: excluded() left no other)
            const Target t = *direct_target(p.bytes, d, p.ip);
            next = t.ip;
            if (t.far) cs = t.cs;
        }
    }
    code.first = code.runs[0].bytes;
    code.ip = pieces[0].ip;
    code.steps = unsigned(pieces.size());
    return code;
}

unsigned WorstClocks::sequence(const std::vector<Piece>& pieces) {
    std::string key;
    const Code code = lay_out(pieces, false, key);
    const auto it = sequences_.find(key);
    if (it != sequences_.end()) return it->second;
    const unsigned c = measure(code, 0xFFFF);
    sequences_.emplace(std::move(key), c);
    return c;
}

Outcomes WorstClocks::branch(const std::vector<Piece>& pieces) {
    std::string key;
    Code code = lay_out(pieces, true, key);
    const auto it = branches_.find(key);
    if (it != branches_.end()) return it->second;
    // The first status flags and CX (1, 2, 0: LOOP falls through, loops, JCXZ jumps) that give
    // each outcome.
    Outcomes o;
    for (bool want : {true, false}) {
        bool found = false;
        for (std::uint16_t cx : {1, 2, 0})
            for (unsigned bits = 0; bits < 32 && !found; ++bits) {
                const std::uint16_t f = std::uint16_t(((bits & 1) ? flag::CF : 0) | ((bits & 2) ? flag::PF : 0) |
                                                      ((bits & 4) ? flag::ZF : 0) | ((bits & 8) ? flag::SF : 0) |
                                                      ((bits & 16) ? flag::OF : 0));
                if (taken(code.branch, f, cx) != want) continue;
                found = true;
                code.forced = true;
                code.force_flags = f;
                code.force_cx = cx;
            }
        (want ? o.taken : o.not_taken) = measure(code, 0xFFFF);
    }
    branches_.emplace(std::move(key), o);
    return o;
}

/// The register set-ups an instruction is measured with: every alignment, and for the forms
/// whose time depends on values (conditional transfers, shifts by CL, string instructions,
/// MUL/IMUL/DIV/IDIV, AAM) the values that can make it longest. `forced`: a line's last branch
/// whose outcome branch() forces (one set-up is enough then).
static std::vector<Setup> setups_for(const std::vector<std::uint8_t>& bytes, bool forced, bool strings,
                                     std::uint32_t cx_max) {
    const Decoded d = decode(bytes.data(), unsigned(bytes.size()));
    const std::uint8_t op = d.opcode;
    const unsigned at = d.prefixes;
    const bool modrm_follows = at + 1 < bytes.size();
    const std::uint8_t modrm = modrm_follows ? bytes[at + 1] : 0;
    const unsigned reg = (modrm >> 3) & 7;
    const bool mem = modrm_follows && (modrm >> 6) != 3;
    bool rep = false;
    for (unsigned i = 0; i < at; ++i) rep = rep || bytes[i] == 0xF2 || bytes[i] == 0xF3;
    const std::uint16_t cx = std::uint16_t(std::min<std::uint32_t>(cx_max, 0xFFFF));
    const bool muldiv = (op == 0xF6 || op == 0xF7) && reg >= 4;

    std::vector<Setup> setups;
    for (const Registers& r : alignments(cx))
        for (Fill f : {Fill::ones, Fill::zeros}) setups.push_back(Setup{r, f});
    // (CBW and CWD take a clock more for a negative accumulator)
    for (int i = 0; i < 4; ++i) {
        Setup s = setups[std::size_t(i)];
        s.regs.r[AX] = s.regs.r[DX] = std::uint16_t(0xFF80 | s.regs.r[AX]);
        setups.push_back(s);
    }
    const std::vector<Setup> aligned = setups;
    auto vary = [&](auto change) {
        std::vector<Setup> out;
        for (const Setup& s : aligned) change(s, out);
        setups.insert(setups.end(), out.begin(), out.end());
    };
    if (d.flow == Flow::branch && forced) { // (branch() writes the outcome's flags and CX)
        setups = {aligned[0]};
    } else if (d.flow == Flow::branch || op == 0xCE) { // Jcc, LOOPx, JCXZ, INTO: taken and not taken
        std::vector<Setup> out;
        for (const Setup& a : op == 0xCE ? aligned : std::vector<Setup>{aligned[0]}) // (INTO pushes)
            for (std::uint16_t f : {std::uint16_t(0), kAllStatus, flag::SF, flag::OF})
                for (std::uint32_t c : {0u, 1u, 2u, cx_max})
                    if (c <= cx_max) {
                        Setup s = a;
                        s.regs.flags = std::uint16_t(0xF002 | f);
                        s.regs.r[CX] = std::uint16_t(std::min<std::uint32_t>(c, 0xFFFF));
                        out.push_back(s);
                    }
        setups = out;
    } else if ((op >= 0xD2 && op <= 0xD3)) { // shifts and rotates by CL: the most and one less
        const std::uint16_t cl = std::min<std::uint16_t>(cx, 255);
        for (Setup& s : setups) s.regs.r[CX] = std::uint16_t((cx & 0xFF00) | cl);
        if (cl) vary([&](const Setup& a, std::vector<Setup>& out) {
            Setup s = a;
            s.regs.r[CX] = std::uint16_t((cx & 0xFF00) | (cl - 1));
            out.push_back(s);
        });
    } else if (strings) { // both directions; CMPS/SCAS finding their byte or not
        vary([&](const Setup& a, std::vector<Setup>& out) {
            for (int df = 0; df < 2; ++df)
                for (Fill f : {Fill::ones, Fill::zeros, Fill::counting})
                    for (std::uint16_t acc : {std::uint16_t(0xFFFF), std::uint16_t(0x0000), std::uint16_t(0x3333)}) {
                        Setup s = a;
                        s.fill = f;
                        s.regs.r[AX] = acc;
                        if (df) s.regs.flags |= flag::DF;
                        out.push_back(s);
                    }
        });
        if (rep && cx > 0) vary([&](const Setup& a, std::vector<Setup>& out) {
            Setup s = a;
            s.regs.r[CX] = std::uint16_t(cx - 1);
            out.push_back(s);
        });
    } else if (muldiv) {
        const bool word = op == 0xF7;
        setups.clear();
        // (a memory operand answers the value itself: its address takes both parities over the
        // first three alignments, whatever registers the ModR/M adds)
        for (const Values& v : muldiv_values(word))
            for (unsigned a = 0; a < (mem ? 3u : 1u); ++a) {
                Setup s = aligned[2 * a];
                s.regs.r[AX] = v.ax;
                s.regs.r[DX] = word ? v.dx : v.operand;
                if (mem) {
                    s.operand = true;
                    s.word = word;
                    s.value = v.operand;
                } else {
                    for (int r : {CX, BX, SP, BP, SI, DI}) s.regs.r[r] = v.operand;
                    if (word && (modrm & 7) == DX) s.regs.r[DX] = v.operand;
                }
                setups.push_back(s);
            }
    } else if (op == 0xD4) { // AAM: every AL
        vary([&](const Setup& a, std::vector<Setup>& out) {
            if (&a != &aligned[0] && &a != &aligned[1]) return;
            for (unsigned al = 0; al < 256; ++al) {
                Setup s = a;
                s.regs.r[AX] = std::uint16_t(al);
                out.push_back(s);
            }
        });
    }
    return setups;
}

unsigned WorstClocks::measure(const Code& code, std::uint32_t cx_max) {
    const std::vector<std::uint8_t>& bytes = code.first;
    const Decoded d = decode(bytes.data(), unsigned(bytes.size()));
    const std::uint8_t op = d.opcode;
    bool rep = false;
    for (unsigned i = 0; i < d.prefixes; ++i) rep = rep || bytes[i] == 0xF2 || bytes[i] == 0xF3;
    const std::uint16_t cx = std::uint16_t(std::min<std::uint32_t>(cx_max, 0xFFFF));
    const unsigned reg = d.prefixes + 1 < bytes.size() ? (bytes[d.prefixes + 1] >> 3) & 7 : 0;
    const bool divide = (op == 0xF6 || op == 0xF7) && reg >= 6;
    std::vector<Setup> setups = setups_for(bytes, code.forced, code.strings, cx_max);
    const bool can_fault = divide || op == 0xD4;

    // A long REP run (a ROM's unknown CX is 65535: 17 clocks an element) would make every run
    // long: the set-ups and BIU states are chosen with a probe count of kRepProbe elements,
    // where the runs differ only in their start, end and per-element rate; the chosen ones
    // then run the whole count.
    const std::vector<Setup> full = setups;
    const bool long_rep = rep && is_string(op) && cx > kRepProbe;
    if (long_rep)
        for (Setup& s : setups) s.regs.r[CX] = std::uint16_t(kRepProbe - (cx - s.regs.r[CX]));

    // Stage 1: every set-up from the first BIU states.
    const std::vector<Preamble> first = first_preambles();
    std::vector<std::pair<unsigned, std::size_t>> by_time; // worst over `first`, set-up
    unsigned worst = 0, worst_fault = 0;
    bool any = false;
    for (std::size_t i = 0; i < setups.size(); ++i) {
        unsigned w = 0;
        bool ok = false;
        for (const Preamble& p : first) {
            bool fault = false;
            const unsigned c = harness_->measure(code, p, setups[i], can_fault, fault);
            if (fault) worst_fault = std::max(worst_fault, c);
            else {
                w = std::max(w, c);
                ok = true;
            }
        }
        if (ok) {
            by_time.push_back({w, i});
            any = true;
        }
    }
    if (!any) return worst_fault; // every run divides by zero or overflows: what those cost
    // Stage 2: the set-ups within a bus cycle of the worst (a distinct time each, at most 6),
    // from every BIU state.
    std::sort(by_time.begin(), by_time.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    const unsigned top = by_time.front().first;
    std::vector<std::size_t> chosen;
    std::vector<unsigned> seen;
    for (const auto& [w, i] : by_time) {
        if (w + 4 + 2 * waits_.data + 2 * waits_.code < top || chosen.size() >= kChosen) break;
        if (std::count(seen.begin(), seen.end(), w) >= 2) continue;
        seen.push_back(w);
        chosen.push_back(i);
    }
    static const std::vector<Preamble> every = all_preambles();
    for (std::size_t i : chosen) {
        std::vector<std::pair<unsigned, std::size_t>> by_state; // time, preamble
        for (std::size_t k = 0; k < every.size(); ++k) {
            bool fault = false;
            const unsigned c = harness_->measure(code, every[k], setups[i], can_fault, fault);
            if (!fault) by_state.push_back({c, k});
        }
        if (!long_rep) {
            for (const auto& [c, k] : by_state) worst = std::max(worst, c);
            continue;
        }
        // (the whole count from the three BIU states the probe found worst)
        std::sort(by_state.begin(), by_state.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
        for (std::size_t j = 0; j < by_state.size() && j < 3; ++j) {
            bool fault = false;
            worst = std::max(worst, harness_->measure(code, every[by_state[j].second], full[i], can_fault, fault));
        }
    }
    return long_rep ? worst : std::max(worst, top);
}

unsigned WorstClocks::interrupt_entry() {
    if (entry_) return entry_;
    Harness& h = *harness_;
    std::vector<Preamble> states = all_preambles();
    Preamble halt;
    add(halt, kPNop, 1);
    halt.bytes.push_back(0xF4);
    halt.halt = true;
    states.push_back(halt);
    Code nop;
    nop.runs.push_back(Run{kCs, 0x0100, {kNop}});
    nop.first = {kNop};
    nop.ip = 0x0100;
    unsigned worst = 0;
    for (Preamble p : states) {
        // (one instruction at least, so that the entry is taken at a boundary step() checks)
        if (p.instructions == 0 && !p.halt) {
            p.bytes.insert(p.bytes.end(), kNop);
            p.instructions = 1;
        }
        for (Fill f : {Fill::ones, Fill::zeros})
            for (std::uint16_t sp : {std::uint16_t(0x8000), std::uint16_t(0x8001)}) {
                h.begin(p, nop);
                h.fill = f;
                h.cpu.regs().r[SP] = sp;
                h.cpu.regs().flags = 0xF002 | flag::IF;
                h.cpu.set_intr(true);
                const cycles_t c0 = h.cpu.cycles();
                h.cpu.step();
                h.cpu.set_intr(false);
                worst = std::max(worst, unsigned(h.cpu.cycles() - c0));
            }
    }
    return entry_ = worst;
}

} // namespace rcsim::i8086
