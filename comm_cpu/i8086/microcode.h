// rcsim — Intel 8086 execution unit: the internal clocks of the EU as named steps.
//
// Each constant is the number of internal clocks (Cpu::clks) one step of an instruction spends,
// named after the microcode routine or lines it stands for, so the execution-unit code reads
// against the published 8086 microcode disassembly (reenigne; the line addresses 000-1FF below
// are those of that listing, as MartyPC's cpu_808x numbers them). Facts only: the counts are
// the ones measured on the captured P80C86A-2 (SingleStepTests 8086 v1, level 3 exact), where
// they agree with the listing its lines are named; where the measure has no clear routine the
// constant is named for what happens and says "measured".
//
// Conventions (docs/cpu8086.md, "Named timing steps"):
// - One micro-instruction is one clock; a taken jump, a call and a return cost one more (the
//   sequencer loads the new address): kJump.
// - The micro-instruction that issues a bus request (R, W, w, IRQ) is inside the BIU's request
//   clocks (eu_bus) and a queue read (Q ->) is a q_read: neither is counted here.
// - A line marked NX can run while the next instruction starts (its clock is then the next
//   opcode read, not counted); a WB,NX line takes a clock of its own only when a memory
//   write-back follows it.
// - Some measured counts are split differently across a REP loop or an INTR entry than the
//   listing's line order; each comment says where.
// - A step is spent with Cpu::clks(step), or with Cpu::clk(step) where the EU has always taken
//   that one clock with clk() (the same clock; see the static_assert at the end).
#pragma once

namespace rcsim::i8086 {

// ---- shared steps ---------------------------------------------------------------------------

/// A taken jump, call or return: one clock for the sequencer to load the new address (also the
/// L8 skip of a byte immediate's Q -> tmpbH line).
constexpr unsigned kJump = 1;
/// SUSP (prefetching stops): the micro-instruction's own clock on an idle bus or at T4.
constexpr unsigned kSuspLine = 1;
/// A FLUSH micro-instruction's own clock (0D5 RELJMP, 081 CALL, 0D9 JMP r/m, 0DF JMP far m,
/// 0E6 JMP far): the flush is reported on the QS lines in it.
constexpr unsigned kFlushLine = 1;
/// CORR: the line and the clock that corrects PC by the bytes still in the queue.
constexpr unsigned kCorr = 2;
/// EALOAD after its read (1E1): 1E2 (OPR -> tmpb) and the return to the instruction.
constexpr unsigned kEaLoadReturn = 2;
/// EADONE: 1E3 (tmpa -> IND) and the return, for an EA that is not loaded (LEA, write-only
/// operands).
constexpr unsigned kEaDone = 2;
/// A register r/m operand where a memory one spends kEaLoadReturn (JMP/CALL near r/m, TEST
/// r/m,imm, PUSH r/m): measured, no line of its own in the listing.
constexpr unsigned kRegOperand = 1;
/// The ALU micro-instruction on the r/m operand: 008 / 00E (XI), 094 / 09A (AND), 020 / 04C /
/// 050 / 088 (XI tmpb).
constexpr unsigned kAluXi = 1;
/// A WB,NX line (009 op r/m,reg; 000 MOV r/m,reg; 0A6 XCHG): a clock of its own before a memory
/// write-back (with a register destination it runs with the next opcode read).
constexpr unsigned kWriteBackTest = 1;
/// The result into M before the write request: SIGMA -> M (00A, 00F, 021, 04D, 051, 089), tmpb
/// -> M (016, 001, 092), tmpa -> M (0A7), R -> M (0EC).
constexpr unsigned kResultToM = 1;

// ---- instruction start and effective address (eu.cpp) -------------------------------

/// A prefix byte: one clock after its read before the next byte is read (no microcode).
constexpr unsigned kPrefix = 1;
/// An opcode without a ModR/M byte: the clock after its read in which the loader starts the
/// microcode (the ModR/M byte is read in that clock otherwise).
constexpr unsigned kLoaderClock = 1;
/// The HLT state: the EU idles one clock per step() until NMI or an enabled INTR.
constexpr unsigned kHaltIdle = 1;
/// After a displacement: 1E0 (SIGMA -> tmpa: the displacement added) and the jump to EAFINISH.
constexpr unsigned kEaDispAdd = 2;

// ---- ALU group (ops_alu.cpp) ----------------------------------------------------------

/// Shift/rotate by CL: 08C-08E (the count from CL into tmpa, the operand into tmpb) and the
/// jump into the loop (the User's Manual's 8 + 4/bit on registers with kShiftClExit).
constexpr unsigned kShiftClSetup = 4;
/// Shift/rotate by CL, per bit: 090 (the shift), 091 (NZ), the jump back, 08F (DEC tmpa).
constexpr unsigned kShiftClPerBit = 4;
/// Shift/rotate by CL: the last 090-091, where the NZ test leaves the loop.
constexpr unsigned kShiftClExit = 2;
/// DAA/DAS: 144-145 (A -> tmpaL with XI, ONES -> tmpb); 146 runs with the next opcode read.
constexpr unsigned kDaaSetup = 2;
/// AAA/AAS: 148-14D, the AF/low-nibble test; without an adjustment 14D's NCY jump adds kJump.
constexpr unsigned kAaaTest = 6;

// ---- moves, stack, I/O (ops_move.cpp) -------------------------------------------------

/// XCHG r/m,reg: 0A4-0A5 (R -> tmpa, M -> tmpb).
constexpr unsigned kXchgLoad = 2;
/// XCHG AX,reg (90-97): 084 (M -> tmpb); 085 runs with the next opcode read.
constexpr unsigned kXchgAxLoad = 1;
/// CWD: 058-05A (the sign of AX into CF, CY 5); a negative AX takes the jump (kJump).
constexpr unsigned kCwdTest = 3;
/// SAHF: 100-101 (F -> tmpa); 102-103 merge AH into the flags with the next opcode read.
constexpr unsigned kSahfLoad = 2;
/// The address into IND on a line of its own before a write: 066 (MOV moffs,AL/AX), 0B2 (OUT
/// imm8), 0B8 (OUT DX).
constexpr unsigned kAddrToInd = 1;
/// IN/OUT imm8: 0AD / 0B1 (ZERO -> tmpbH): the port byte widened to 16 bits.
constexpr unsigned kPortWiden = 1;
/// LES/LDS: 0F0 / 0F4 (OPR -> R): the offset into the register.
constexpr unsigned kLdsOffset = 1;
/// A far pointer: IND -> tmpc, INC2 tmpc (068 CALL far m, 0DC JMP far m, 0F1 / 0F5 LES/LDS):
/// the address of its segment word.
constexpr unsigned kFarPtrSegAddr = 1;
/// XLAT: 10C-10E (ZERO -> tmpa, AL -> tmpaL, BX -> tmpb with ADD) before 10F reads BX + AL.
constexpr unsigned kXlatAddr = 3;
/// PUSH: SP -> tmpa with DEC2, SIGMA -> IND, SIGMA -> SP (024-026 r/m, 028-02A reg, 02C-02E
/// sreg, 030-032 PUSHF) before the stack write.
constexpr unsigned kPushSetup = 3;
/// POP r/m: 040, the line before the stack read.
constexpr unsigned kPopRmStart = 1;
/// POP r/m: 042 (IND -> SP) after the stack read.
constexpr unsigned kPopRmSp = 1;
/// POP r/m to memory: 043-044 before the write to the operand.
constexpr unsigned kPopRmToMem = 2;

// ---- string instructions and REP (ops_move.cpp) ---------------------------------------

/// The F1 RPTS line a string routine begins with (11C STOS, 120 CMPS/SCAS, 12C LODS). Inside a
/// REP run the same clock is RPTS's return or the jump back to the element.
constexpr unsigned kRptsTest = 1;
/// CMPS/SCAS: 121 (M -> tmpa, X0 5): CMPS goes on to read DS:SI, SCAS jumps to 125 (kJump).
constexpr unsigned kCmpsScasSelect = 1;
/// CMPS between its reads: 123-124 (IND -> IJ, OPR -> tmpa).
constexpr unsigned kCmpsKeepFirst = 2;
/// CMPS/SCAS after the ES:DI read: 126 (SUBT), 127 (DEC tmpc, flags), 128 (NF1) and its jump out
/// (inside a REP run: 129's F1ZZ test instead of the jump).
constexpr unsigned kStrCompare = 4;
/// MOVS: 12E (IND -> IJ) between the read and the write (MOVS is not in the captures).
constexpr unsigned kMovsStep = 1;
/// STOS after the write: 11E (IND -> IK) and its NF1 jump out (inside a REP run 11E-11F).
constexpr unsigned kStosStep = 2;
/// LODS after the read: 12E (X0 8), its jump and 1F8 (OPR -> M: into AL/AX).
constexpr unsigned kLodsStep = 3;
/// REP, first element: the routine's F1 RPTS line and the call, 112 (BC -> tmpc), 113 (DEC tmpc).
constexpr unsigned kRepStart = 4;
/// RPTS 114 (NZ): CX = 0 ends the instruction (115 RNI).
constexpr unsigned kRptsCxTest = 1;
/// RPTS with CX != 0: 114, its jump and 116 (RTN); the return is the element's first clock.
constexpr unsigned kRptsToElement = 3;
/// Between elements while a REP run goes on: the loop's INT RPTI and NZ lines (12A-12B CMPS/SCAS,
/// 131-132 LODS after 1F8's jump; MOVS, not captured, keeps 2 as an estimate); the jump back is
/// the next element's first clock.
constexpr unsigned kRepNext = 2;
/// STOS between elements: 1F0 (tmpc -> BC, NZ); its INT RPTI line (11F) is in kStosStep.
constexpr unsigned kRepNextStos = 1;

// ---- control transfer (ops_control.cpp, RELJMP/SUSP in biu.cpp) -----------------

/// Jcc, LOOP, LOOPE/LOOPNE, JCXZ: the branch test after the displacement read (Jcc 0E9, XC
/// RELJMP; LOOPE/LOOPNE 13B, JCXZ 137, or the jump out of 13A / 136 when not taken; LOOP tests
/// with the read (142): its jump into RELJMP, or 143).
constexpr unsigned kBranchTest = 1;
/// LOOP/LOOPE/LOOPNE/JCXZ: CX (- 1) through the ALU before the displacement is read (140-141,
/// 138-139, 134-135).
constexpr unsigned kLoopCount = 2;
/// RELJMP 0D4 / CALL 080 (PC -> tmpa, ADD): the displacement added, after CORR.
constexpr unsigned kReljmpAdd = 1;
/// CALL rel16: 082 (IND -> SP, UNC 7) and its jump, before 083 pushes the return IP.
constexpr unsigned kCallRelPush = 2;
/// JMP far: 0E5 (tmpb -> PC) between SUSP and the flush.
constexpr unsigned kJmpFarPc = 1;
/// CALL near r/m: 076 (PC -> OPR, DEC2 tmpc) after CORR: the return IP into OPR.
constexpr unsigned kCallRetToOpr = 1;
/// CALL far m: 06A (OPR -> tmpa) after the segment read, before SUSP and CORR.
constexpr unsigned kCallFarMSeg = 1;
/// FARCALL after the CS push: 06E (tmpa -> RC), 06F (PC -> OPR, UNC NEARCALL) and the jump.
constexpr unsigned kFarCallToNear = 3;
/// NEARCALL from its flush: 077 (tmpb -> PC, FLUSH), 078-079, before 07A pushes the return IP.
constexpr unsigned kNearCall = 3;
/// RETF / IRET: 0C0 / 0C8 (UNC FARRET) and the jump into FARRET.
constexpr unsigned kFarRetCall = 2;
/// FARRET after the IP read: 0C3 (SUSP), 0C4 (OPR -> PC, X0 6; a far return takes the jump).
constexpr unsigned kFarRetSusp = 2;
/// FARRET after the flush: 0C5 / 0C7 (FLUSH RTN) and the return.
constexpr unsigned kFarRetTail = 2;
/// RET: 0BE (OPR -> PC, FLUSH) and 0BF (IND -> SP).
constexpr unsigned kRetTail = 2;

// ---- interrupts (ops_control.cpp, eu.cpp) ---------------------------------------

/// INT n after the type byte (1A8's read): measured 2 (the listing's jump to INTR is one).
constexpr unsigned kIntImm = 2;
/// INT 3: 1B0 (UNC 2) and its jump over 1B1.
constexpr unsigned kInt3Skip = 2;
/// CR -> tmpbL (the type constant), UNC INTR and the jump (1B2 INT 3, 1AF INTO).
constexpr unsigned kTypeToIntr = 2;
/// INTO: 1AC-1AD, the OF test; OF set takes 1AD's jump (kJump).
constexpr unsigned kIntoTest = 2;
/// INTR pin: one clock before the INTA pair (no hardware capture covers the INTR entry).
constexpr unsigned kIrqToInta = 1;
/// INTR pin: one clock after the INTA pair, before the INTR routine (no capture either).
constexpr unsigned kIntaToIntr = 1;
/// INTR 19E-19F: the vector address (type * 4) formed before 1A0 reads the new IP (19D's clock
/// is susp() at the entry: prefetching stops there as measured, where the listing has SUSP at
/// 1A3).
constexpr unsigned kIntrVectorAddr = 2;
/// INTR 1A1 (OPR -> tmpb, DEC2 tmpc) between the IP read and the CS read (1A2).
constexpr unsigned kIntrIpToCs = 1;
/// INTR 1A3-1A4 (OPR -> tmpa, F -> OPR with CITF) before 1A5 pushes FLAGS (1A3's SUSP is
/// already done at the entry).
constexpr unsigned kIntrCsToFlags = 2;
/// INTR 1A6 (IND -> tmpc, UNC FARCALL2) and the jump; FARCALL2 goes on with 06C's CORR.
constexpr unsigned kIntrToFarCall2 = 2;

// ---- flag operations, HLT, WAIT, SALC, ESC (exec.cpp) ---------------------------------

/// WAIT with TEST# active (held so on this board): measured 3.
constexpr unsigned kWaitTestActive = 3;
/// SALC: 0A0 (CY 2), the CF test; with CF = 1 its jump adds kJump.
constexpr unsigned kSalcTest = 1;
/// HLT: one clock after prefetching stops, then the halt state (measured).
constexpr unsigned kHaltEnter = 1;

// ---- MUL/DIV/AAM around the microcode (muldiv.cpp) ------------------------------------

/// MUL/DIV with a memory operand: one clock more before the sequence (measured).
constexpr unsigned kMulDivMemOperand = 1;
/// MUL/DIV: the last result move before the next opcode read (157 / 15F, 166 / 16E).
constexpr unsigned kMulDivResult = 1;
/// DIV/IDIV divide error: to the type-0 entry (1A7 CR -> tmpbL and the jump to INTR among them;
/// measured 3).
constexpr unsigned kDivToInt0 = 3;
/// AAM with a zero base: to the type-0 entry (measured).
constexpr unsigned kAamZeroBase = 2;
/// AAM: the CORD division of AL by the base, measured: kAamLoop clocks, kAamPerQuotientOne per
/// one bit of the quotient, kAamOddQuotient more when the quotient is odd.
constexpr unsigned kAamLoop = 74;
constexpr unsigned kAamPerQuotientOne = 1;
constexpr unsigned kAamOddQuotient = 2;

// The steps the EU spends with Cpu::clk(step), one plain clock each.
static_assert(kJump == 1 && kSuspLine == 1 && kFlushLine == 1 && kPrefix == 1 && kLoaderClock == 1 &&
                  kHaltIdle == 1 && kBranchTest == 1 && kJmpFarPc == 1 && kAddrToInd == 1 && kPopRmStart == 1 &&
                  kPopRmSp == 1,
              "Cpu::clk(step) spends one clock");

} // namespace rcsim::i8086
