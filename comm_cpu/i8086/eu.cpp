// rcsim — Intel 8086 execution unit: decode, operands, instructions, interrupts.
//
// Documentation: iAPX 86/88 User's Manual (Intel 210201), instruction set reference and
// clock tables; undocumented behaviour (aliases 60-6F/C0/C1/C8/C9/82/F6.1/FF.7, SALC D6,
// SETMO/SETMOC D0-D3 /6, POP CS 0F, MOV CS, the REP prefix negating the IMUL/IDIV result,
// IDIV refusing the most negative quotient, the divide error pushing the address of the next
// instruction) as captured on a P80C86A-2 in the SingleStepTests 8086 suite.
//
// Timing: every clock the EU spends is explicit: a queue read (q_read, 1 clock), an internal
// clock (clks), or a bus cycle through the BIU (eu_bus). Internal clock counts are the named
// microcode steps of microcode.h, as observed on the captured hardware (docs/cpu8086.md).
#include "comm_cpu/i8086/cpu.h"
#include "comm_cpu/i8086/microcode.h"

namespace rcsim::i8086 {
namespace {

// Parity flag: set when the low byte has an even number of one bits.
constexpr bool parity(std::uint8_t v) {
    v ^= v >> 4;
    v ^= v >> 2;
    v ^= v >> 1;
    return !(v & 1);
}

constexpr SegStatus seg_status(int seg) {
    switch (seg) {
    case ES: return SegStatus::ES;
    case SS: return SegStatus::SS;
    case CS: return SegStatus::CS;
    default: return SegStatus::DS;
    }
}

// Opcodes whose second byte is a ModR/M byte (read in the clock right after the opcode).
constexpr bool modrm_form(unsigned op) {
    if (op < 0x40) return (op & 0x04) == 0;
    if (op >= 0x80 && op <= 0x8F) return true;
    if (op == 0xC4 || op == 0xC5 || op == 0xC6 || op == 0xC7) return true;
    if (op >= 0xD0 && op <= 0xD3) return true;
    if (op >= 0xD8 && op <= 0xDF) return true;
    if (op == 0xF6 || op == 0xF7 || op == 0xFE || op == 0xFF) return true;
    return false;
}

// The same as a table (step() asks it for every instruction).
struct ModrmTable {
    bool has[256];
    constexpr ModrmTable() : has() {
        for (unsigned op = 0; op < 256; ++op) has[op] = modrm_form(op);
    }
};
constexpr ModrmTable kModrm{};
constexpr bool has_modrm(std::uint8_t op) { return kModrm.has[op]; }

} // namespace

// ---------------------------------------------------------------------------------------------
// Memory and I/O operands. A word at an odd address is two byte cycles (A0/BHE lanes).

std::uint8_t Cpu::read8(int seg, std::uint16_t off) {
    const std::uint32_t a = linear(r_.s[seg], off);
    const std::uint16_t d = eu_bus(Bus::mem_read, seg_status(seg), a, 0, 1, false);
    return (a & 1) ? std::uint8_t(d) : std::uint8_t(d);
}

std::uint16_t Cpu::read16(int seg, std::uint16_t off) {
    const std::uint32_t a = linear(r_.s[seg], off);
    if (!(a & 1)) return eu_bus(Bus::mem_read, seg_status(seg), a, 0, 2, false);
    const std::uint8_t lo = std::uint8_t(eu_bus(Bus::mem_read, seg_status(seg), a, 0, 1, false));
    const std::uint32_t a2 = linear(r_.s[seg], std::uint16_t(off + 1));
    const std::uint8_t hi = std::uint8_t(eu_bus(Bus::mem_read, seg_status(seg), a2, 0, 1, false));
    return std::uint16_t(lo | (hi << 8));
}

void Cpu::write8(int seg, std::uint16_t off, std::uint8_t v, bool last) {
    eu_bus(Bus::mem_write, seg_status(seg), linear(r_.s[seg], off), v, 1, last);
}

void Cpu::write16(int seg, std::uint16_t off, std::uint16_t v, bool last) {
    const std::uint32_t a = linear(r_.s[seg], off);
    if (!(a & 1)) {
        eu_bus(Bus::mem_write, seg_status(seg), a, v, 2, last);
        return;
    }
    eu_bus(Bus::mem_write, seg_status(seg), a, v & 0xFF, 1, false);
    eu_bus(Bus::mem_write, seg_status(seg), linear(r_.s[seg], std::uint16_t(off + 1)), v >> 8, 1, last);
}

std::uint16_t Cpu::in(std::uint16_t port, bool word) {
    if (!word) return eu_bus(Bus::io_read, SegStatus::none, port, 0, 1, false) & 0xFF;
    if (!(port & 1)) return eu_bus(Bus::io_read, SegStatus::none, port, 0, 2, false);
    const std::uint8_t lo = std::uint8_t(eu_bus(Bus::io_read, SegStatus::none, port, 0, 1, false));
    const std::uint8_t hi =
        std::uint8_t(eu_bus(Bus::io_read, SegStatus::none, std::uint16_t(port + 1), 0, 1, false));
    return std::uint16_t(lo | (hi << 8));
}

void Cpu::out(std::uint16_t port, std::uint16_t v, bool word, bool last) {
    if (!word) {
        eu_bus(Bus::io_write, SegStatus::none, port, v & 0xFF, 1, last);
    } else if (!(port & 1)) {
        eu_bus(Bus::io_write, SegStatus::none, port, v, 2, last);
    } else {
        eu_bus(Bus::io_write, SegStatus::none, port, v & 0xFF, 1, false);
        eu_bus(Bus::io_write, SegStatus::none, std::uint16_t(port + 1), v >> 8, 1, last);
    }
}

void Cpu::push(std::uint16_t v, bool last) {
    r_.r[SP] = std::uint16_t(r_.r[SP] - 2);
    write16(SS, r_.r[SP], v, last);
}

std::uint16_t Cpu::pop() {
    const std::uint16_t v = read16(SS, r_.r[SP]);
    r_.r[SP] = std::uint16_t(r_.r[SP] + 2);
    return v;
}

// ---------------------------------------------------------------------------------------------
// ModR/M and effective address.

void Cpu::decode_modrm() {
    modrm_ = imm8();
    mod_ = modrm_ >> 6;
    reg_ = (modrm_ >> 3) & 7;
    rm_ = modrm_ & 7;
    if (mod_ != 3) calc_ea();
}

// EA clocks as measured on the P80C86A-2 (clocks after the ModR/M read until the EU asks for
// the operand), as the EA routines of the microcode listing run: the jump into the routine,
// its lines and its jump to EAOFFSET: [BX+SI] 1D4-1D6 and [BP+DI] 1D7-1D9 (5 clocks in all),
// [BX+DI] 1DA and a jump to 1D8-1D9, [BP+SI] 1DB and a jump to 1D5-1D6 (6), a base or index
// register alone 003 [SI], 01F [DI], 023 [BP], 037 [BX] (3). Without a displacement the EA is
// complete with that last jump; EAOFFSET reads a displacement (1DE-1DF) and adds it (kEaDispAdd;
// after a byte, 1DE's MOD1 jump over 1DF first). [disp16] is a routine of its own: the jump into
// it, the displacement (1DC-1DD), the jump to EAFINISH. Then EALOAD reads the operand or EADONE
// completes a write-only one (kEaLoadReturn, kEaDone: counted by the instructions). The same EA
// clocks hold for every instruction form (read, write, read-modify-write, LEA).
void Cpu::calc_ea() {
    static constexpr std::uint8_t pre[8] = {5, 6, 6, 5, 3, 3, 3, 3}; // to the jump to EAOFFSET
    std::uint16_t ea = 0;
    if (mod_ == 0 && rm_ == 6) {
        clk(kJump);
        ea = imm16();
        ea_seg_ = DS;
        clk(kJump); // 1DD's UNC EAFINISH
    } else {
        switch (rm_) {
        case 0: ea = r_.r[BX] + r_.r[SI]; ea_seg_ = DS; break;
        case 1: ea = r_.r[BX] + r_.r[DI]; ea_seg_ = DS; break;
        case 2: ea = r_.r[BP] + r_.r[SI]; ea_seg_ = SS; break;
        case 3: ea = r_.r[BP] + r_.r[DI]; ea_seg_ = SS; break;
        case 4: ea = r_.r[SI]; ea_seg_ = DS; break;
        case 5: ea = r_.r[DI]; ea_seg_ = DS; break;
        case 6: ea = r_.r[BP]; ea_seg_ = SS; break;
        case 7: ea = r_.r[BX]; ea_seg_ = DS; break;
        }
        static constexpr std::uint8_t pre0[8] = {4, 5, 5, 4, 2, 2, 2, 2}; // pre[] before that jump
        clks(mod_ == 0 ? pre0[rm_] : pre[rm_]);
        if (mod_ == 1) {
            ea = std::uint16_t(ea + std::int8_t(imm8()));
            clks(kJump + kEaDispAdd);
        } else if (mod_ == 2) {
            ea = std::uint16_t(ea + imm16());
            clks(kEaDispAdd);
        } else {
            clk(kJump); // UNC EAOFFSET, the EA complete without a displacement
        }
    }
    ea_ = ea;
    if (seg_override_ >= 0) ea_seg_ = seg_override_;
}

std::uint8_t Cpu::rm_read8() { return mod_ == 3 ? reg8(rm_) : read8(ea_seg_, ea_); }
std::uint16_t Cpu::rm_read16() { return mod_ == 3 ? r_.r[rm_] : read16(ea_seg_, ea_); }

void Cpu::rm_write8(std::uint8_t v, bool last) {
    if (mod_ == 3) set_reg8(rm_, v);
    else write8(ea_seg_, ea_, v, last);
}

void Cpu::rm_write16(std::uint16_t v, bool last) {
    if (mod_ == 3) r_.r[rm_] = v;
    else write16(ea_seg_, ea_, v, last);
}

// ---------------------------------------------------------------------------------------------
// ALU.

// SF, ZF and PF of a result, as bits of the flags word. (always_inline: inlined alike in the
// profile-generating copy of the core; comm_cpu/tools/pgo/README.md.)
[[gnu::always_inline]] static inline std::uint16_t szp_bits(std::uint16_t v, bool word) {
    const std::uint16_t sign = word ? 0x8000 : 0x80;
    const std::uint16_t mask = word ? 0xFFFF : 0xFF;
    return std::uint16_t(((v & sign) ? flag::SF : 0) | ((v & mask) == 0 ? flag::ZF : 0) |
                         (parity(std::uint8_t(v)) ? flag::PF : 0));
}

void Cpu::set_szp(std::uint16_t v, bool word) {
    r_.flags = std::uint16_t((r_.flags & ~(flag::SF | flag::ZF | flag::PF)) | szp_bits(v, word));
}

// op: 0 ADD, 1 OR, 2 ADC, 3 SBB, 4 AND, 5 SUB, 6 XOR, 7 CMP. The six arithmetic flags are
// composed as one word and stored once (every ALU instruction passes here).
std::uint16_t Cpu::alu(unsigned op, std::uint16_t a, std::uint16_t b, bool word) {
    const std::uint32_t mask = word ? 0xFFFF : 0xFF;
    const std::uint32_t sign = word ? 0x8000 : 0x80;
    std::uint32_t res = 0;
    std::uint16_t f = 0; // CF, OF, AF (AF is bit 4 of the flags, as of the carry out of bit 3)
    switch (op) {
    case 0:
    case 2: {
        const std::uint32_t c = (op == 2 && get_flag(flag::CF)) ? 1 : 0;
        res = std::uint32_t(a) + b + c;
        if (res > mask) f |= flag::CF;
        if ((a ^ res) & (b ^ res) & sign) f |= flag::OF;
        f |= (a ^ b ^ res) & flag::AF;
        break;
    }
    case 3:
    case 5:
    case 7: {
        const std::uint32_t c = (op == 3 && get_flag(flag::CF)) ? 1 : 0;
        res = std::uint32_t(a) - b - c;
        if (std::uint32_t(a) < std::uint32_t(b) + c) f |= flag::CF;
        if ((a ^ b) & (a ^ res) & sign) f |= flag::OF;
        f |= (a ^ b ^ res) & flag::AF;
        break;
    }
    case 1: res = a | b; break;
    case 4: res = a & b; break;
    case 6: res = a ^ b; break;
    }
    res &= mask;
    constexpr std::uint16_t kArith = flag::CF | flag::PF | flag::AF | flag::ZF | flag::SF | flag::OF;
    r_.flags = std::uint16_t((r_.flags & ~kArith) | f | szp_bits(std::uint16_t(res), word));
    return std::uint16_t(res);
}

// op: 0 ROL, 1 ROR, 2 RCL, 3 RCR, 4 SHL, 5 SHR, 6 SETMO, 7 SAR. The 8086 does not mask the count.
std::uint16_t Cpu::shift(unsigned op, std::uint16_t v, unsigned count, bool word) {
    if (count == 0) return v;
    const std::uint16_t mask = word ? 0xFFFF : 0xFF;
    const std::uint16_t sign = word ? 0x8000 : 0x80;
    bool cf = get_flag(flag::CF), of = get_flag(flag::OF);
    for (unsigned i = 0; i < count; ++i) {
        switch (op) {
        case 0: cf = v & sign; v = std::uint16_t(((v << 1) | cf) & mask); of = bool(v & sign) != cf; break;
        case 1:
            cf = v & 1;
            v = std::uint16_t((v >> 1) | (cf ? sign : 0));
            of = bool(v & sign) != bool(v & (sign >> 1));
            break;
        case 2: {
            const bool out = v & sign;
            v = std::uint16_t(((v << 1) | cf) & mask);
            cf = out;
            of = bool(v & sign) != cf;
            break;
        }
        case 3: {
            const bool out = v & 1;
            v = std::uint16_t((v >> 1) | (cf ? sign : 0));
            cf = out;
            of = bool(v & sign) != bool(v & (sign >> 1));
            break;
        }
        case 4: cf = v & sign; v = std::uint16_t((v << 1) & mask); of = bool(v & sign) != cf; break;
        case 5: cf = v & 1; of = v & sign; v = std::uint16_t(v >> 1); break;
        case 6: v = mask; cf = false; of = false; break;
        case 7: cf = v & 1; v = std::uint16_t((v >> 1) | (v & sign)); of = false; break;
        }
    }
    set_flag(flag::CF, cf);
    set_flag(flag::OF, of);
    if (op >= 4) {
        set_szp(v, word);
        set_flag(flag::AF, op == 6 ? false : get_flag(flag::AF));
    }
    return v;
}

bool Cpu::condition(unsigned cc) const {
    const std::uint16_t f = r_.flags;
    bool r = false;
    switch (cc >> 1) {
    case 0: r = f & flag::OF; break;
    case 1: r = f & flag::CF; break;
    case 2: r = f & flag::ZF; break;
    case 3: r = (f & flag::CF) || (f & flag::ZF); break;
    case 4: r = f & flag::SF; break;
    case 5: r = f & flag::PF; break;
    case 6: r = bool(f & flag::SF) != bool(f & flag::OF); break;
    case 7: r = (f & flag::ZF) || (bool(f & flag::SF) != bool(f & flag::OF)); break;
    }
    return (cc & 1) ? !r : r;
}

// ---------------------------------------------------------------------------------------------
// Control transfer.

void Cpu::jump_near(std::uint16_t ip) {
    r_.ip = ip;
    flush_queue();
}

void Cpu::jump_far(std::uint16_t cs, std::uint16_t ip) {
    r_.s[CS] = cs;
    r_.ip = ip;
    flush_queue();
}

// The NEARCALL microcode tail: jump (the flush is reported in the next clock), 077-079, push the
// return IP (07A).
void Cpu::call_near(std::uint16_t ip) {
    const std::uint16_t ret = r_.ip;
    jump_near(ip);
    clks(kNearCall);
    push(ret, true);
}

// The FARCALL tail shared by CALL far and interrupt entry: push CS (06D), 06E-06F and the jump,
// NEARCALL.
void Cpu::call_far(std::uint16_t cs, std::uint16_t ip) {
    push(r_.s[CS]);
    clks(kFarCallToNear);
    r_.s[CS] = cs;
    call_near(ip);
}

// Interrupt entry (INT n, exceptions, NMI, INTR): for INTR two INTA cycles fetch the type;
// then read the vector, push FLAGS, clear IF/TF, push CS, push IP, continue at the handler.
void Cpu::interrupt(std::uint8_t vector, bool hardware_inta) {
    halted_ = false;
    if (hardware_inta) {
        // LOCK is asserted from T2 of the first INTA to T2 of the second; the 8259A drives
        // the type on D7-D0 in the second.
        suspend_fetch();
        clks(kIrqToInta);
        eu_bus(Bus::int_ack, SegStatus::none, 0, 0, 1, false);
        vector = std::uint8_t(eu_bus(Bus::int_ack, SegStatus::none, 0, 0, 1, false));
        clks(kIntaToIntr);
    }
    // The INTR routine from SUSP on (measured on the P80C86A-2 for INT n): 19E-19F, read IP
    // (1A0), 1A1, read CS (1A2), 1A3-1A4, push FLAGS (1A5), 1A6 and the jump to FARCALL2, 06C
    // (CORR), then FARCALL from its CS push (06D) and NEARCALL.
    susp(); // a prefetch in progress completes first
    clks(kIntrVectorAddr);
    const std::uint32_t ivt = std::uint32_t(vector) * 4;
    const std::uint16_t new_ip = eu_bus(Bus::mem_read, SegStatus::none, ivt, 0, 2, false);
    clks(kIntrIpToCs);
    const std::uint16_t new_cs = eu_bus(Bus::mem_read, SegStatus::none, ivt + 2, 0, 2, false);
    clks(kIntrCsToFlags);
    const std::uint16_t old_flags = r_.flags;
    if (old_flags & flag::IF)
        note_if(false, entry_at_boundary_ ? IfChange::How::entry : IfChange::How::instruction,
                entry_at_boundary_ ? 0 : opcode_, vector);
    entry_at_boundary_ = false;
    set_flag(flag::IF, false);
    set_flag(flag::TF, false);
    push(old_flags);
    clks(kIntrToFarCall2 + kCorr);
    call_far(new_cs, new_ip);
    halted_ = false;
}

// NMI (edge), INTR (level, IF=1) and the single-step trap, checked at an instruction
// boundary unless the instruction just executed inhibits it (MOV/POP sreg, STI).
bool Cpu::check_interrupts() {
    if (inhibit_) {
        inhibit_ = false;
        return false;
    }
    if (rep_interrupted_) {
        // A REP run stopped between elements for a pending interrupt: take it now.
        rep_interrupted_ = false;
        if (!nmi_pending_ && !(intr_ && get_flag(flag::IF))) {
            flush_queue(); // the request went away: resume at the prefix
            opcode_ = q_read(QueueOp::first);
            return false;
        }
    }
    const bool nmi = nmi_pending_, intr = intr_ && get_flag(flag::IF), trap = trap_armed_ && get_flag(flag::TF);
    if (!nmi && get_flag(flag::IF) && interrupts_enabled_at_ == kNever)
        interrupts_enabled_at_ = cycle_; // the end of start-up: INTR could be taken here
    if (!nmi && !intr && !trap) return false;
    // Taken here: the boundary, for the probe (interrupt_boundary()) and the IF history.
    intr_boundary_ = cycle_;
    intr_from_halt_ = halted_;
    entry_at_boundary_ = true;
    if (nmi) {
        nmi_pending_ = false;
        interrupt(2);
    } else if (intr) {
        interrupt(0, true);
    } else {
        interrupt(1);
    }
    return true;
}

void Cpu::note_held(Bus kind, std::uint32_t addr, cycles_t start, unsigned waits) {
    if (kind == Bus::mem_read || kind == Bus::mem_write || kind == Bus::code_fetch)
        held_ring_[held_count_++ % kHeldHistory] = HeldCycle{start, addr, waits, kind};
}

void Cpu::note_if(bool enabled, IfChange::How how, std::uint8_t opcode, std::uint8_t vector) {
    IfChange c;
    c.enabled = enabled;
    c.how = how;
    c.opcode = opcode;
    c.vector = vector;
    c.instructions = instructions_;
    if (how == IfChange::How::entry) {
        c.cycle = intr_boundary_;
        c.cs = r_.s[CS];
        c.ip = r_.ip; // the pre-read opcode dropped: IP still points at it
    } else {
        c.cycle = instr_start_;
        c.cs = instr_cs_;
        c.ip = instr_ip_;
    }
    push_if(c);
    if (ff_recording_) {
        if (ff_if_log_.size() < kFfMaxWrites) ff_if_log_.push_back(c);
        else ff_recording_ = false;
    }
}

// ---------------------------------------------------------------------------------------------
// Instruction loop.

void Cpu::start() {
    opcode_ = q_read(QueueOp::first);
    started_ = true;
}

void Cpu::step() {
    if (!started_) start();
    // The boundary before the pre-read opcode: NMI, INTR and the trap are recognised here, with
    // the levels as they were before this clock. The opcode byte already read is dropped (IP
    // still points at it) when an interrupt is taken.
    if (boundary_pending_) {
        boundary_pending_ = false;
        // (the cheap test first: nothing to check when no request, inhibit or trap is set and
        // the end of start-up is not due: it is seen at the first boundary with IF = 1,
        // interrupts_enabled_at)
        if ((inhibit_ || rep_interrupted_ || nmi_pending_ || intr_ || trap_armed_ ||
             (interrupts_enabled_at_ == kNever && get_flag(flag::IF))) &&
            check_interrupts()) {
            opcode_ = q_read(QueueOp::first);
            return;
        }
    }
    if (halted_) {
        clk(kHaltIdle); // HLT: the EU idles until NMI or an enabled INTR
        boundary_pending_ = true;
        return;
    }
    if (rep_suspended_) {
        // A REP run parked between elements: an interrupt is taken here (IP back to the last
        // prefix), otherwise the run continues with the same prefixes.
        if (nmi_pending_ || (intr_ && get_flag(flag::IF))) {
            rep_suspended_ = false;
            r_.ip = std::uint16_t(r_.ip - 2);
            check_interrupts();
            opcode_ = q_read(QueueOp::first);
            return;
        }
        lock_pin_ = lock_;
        execute(opcode_);
        if (rep_suspended_) return;
        lock_pin_ = false;
        ++instructions_;
        boundary_pending_ = true;
        if (halted_ || rep_interrupted_) return;
        opcode_ = q_read(QueueOp::first);
        return;
    }
    if (!step_hook_done_) {
        ++boundaries_;
        if (step_hook_ && step_hook_(step_hook_ctx_, *this)) {
            step_hook_done_ = true;
            stop_ = true;
            return;
        }
    }
    step_hook_done_ = false;
    instr_ip_ = r_.ip;
    instr_cs_ = r_.s[CS];
    instr_start_ = cycle_;
    seg_override_ = -1;
    rep_ = 0;
    lock_ = false;
    trap_armed_ = get_flag(flag::TF);
    std::uint8_t op = opcode_;
    ++r_.ip;
    // Prefixes: no interrupt is taken between a prefix and its instruction.
    for (;;) {
        if ((op & 0xE7) == 0x26) {
            seg_override_ = (op >> 3) & 3;
        } else if (op == 0xF2 || op == 0xF3) {
            rep_ = op;
        } else if (op == 0xF0 || op == 0xF1) {
            lock_ = true;
            lock_pin_ = true; // LOCK# from the prefix to the end of the instruction
        } else {
            break;
        }
        clk(kPrefix);
        op = q_read(QueueOp::first);
        ++r_.ip;
    }
    opcode_ = op;
    rep_interrupted_ = false;
    if (has_modrm(op)) decode_modrm();
    else clk(kLoaderClock);
    execute(op);
    if (rep_suspended_) return; // parked inside a REP run at the end of a slice
    lock_pin_ = false;
    ++instructions_;
    boundary_pending_ = true;
    if (halted_ || rep_interrupted_) return; // no next opcode is read: HLT, or a REP run cut short
    opcode_ = q_read(QueueOp::first);
}

void Cpu::skip_to(cycles_t c) {
    // HLT: the bus stays idle; no clocks need to be simulated one by one.
    if (c > cycle_) {
        cycle_ = c;
        ff_recording_ = false; // time passed that no recorded period can repeat
    }
}

void Cpu::run_until(cycles_t limit, bool burn_halt, cycles_t horizon) {
    stop_ = false;
    limit_ = limit;
    horizon_ = horizon > limit ? horizon : limit;
    struct Reset {
        Cpu& c;
        ~Reset() { c.limit_ = c.horizon_ = ~cycles_t(0); }
    } reset_limit{*this};
    // The fast-forward skips instructions: not while something observes each one or each clock
    // (a step hook with a SkipHook only counts them: it is told which ones were skipped).
    const bool forward = ff_on_ && (!step_hook_ || skip_hook_) && !trace_;
    while (!stop_ && (cycle_ < limit_ || next_slice())) {
        if (halted_ && !nmi_pending_ && !(intr_ && get_flag(flag::IF))) {
            if (!burn_halt) return;
            skip_to(limit_);
            return;
        }
        if (forward && ff_visit()) continue;
        step();
    }
}


} // namespace rcsim::i8086
