// The per-instruction worst clocks (comm_cpu/i8086/worst_clocks.h): no hardware-captured
// SingleStepTests vector takes more clocks than the bound of its bytes at its IP with its CX,
// and the bounds hold the iAPX 86/88 User's Manual's clock figures (Intel 231455's table),
// plus what the wait states add. A straight line's bound (sequence()): one piece's is the
// instruction's, several pieces' lie between the manual's sum and the sum of their bounds.
#include "comm_cpu/i8086/disasm.h"
#include "comm_cpu/i8086/sst.h"
#include "comm_cpu/i8086/worst_clocks.h"
#include "tests/support/files.h"
#include "tests/support/sc_test.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <iostream>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using rcsim::i8086::Piece;
using rcsim::i8086::WaitBounds;
using rcsim::i8086::WorstClocks;

namespace {

/// The board's wait states (comm_board.h's defaults: one on ROM and I/O cycles, data at the worst
/// region's one).
const WaitBounds kBoardWaits{1, 1, 1, 0};

unsigned bound(WorstClocks& w, std::vector<std::uint8_t> b, std::uint32_t cx_max = 0xFFFF, std::uint16_t ip = 0x100) {
    return w.instruction(b.data(), static_cast<unsigned>(b.size()), ip, cx_max);
}

// The files are dealt to kShards ctest entries (file index modulo kShards) so CI's two cores
// share them.
constexpr unsigned kShards = 4;

// Whether a run of the vector read the divide error's vector (00000-00003) on our core, which
// reproduces the capture's cycles: such a run is not a time of the instruction (worst_clocks.h).
bool divide_error(const rcsim::i8086::sst::Runner::Timing& t) {
    for (const rcsim::i8086::BusRecord& r : t.bus)
        if (r.kind == rcsim::i8086::Bus::mem_read && r.address < 4) return true;
    return false;
}

class WorstClocksVectors : public ::testing::TestWithParam<unsigned> {};

} // namespace

TEST_P(WorstClocksVectors, NoVectorTakesMoreThanItsBound) {
    using namespace rcsim::i8086::sst;
    const std::string dir = rcsim::test::sst_dir();
    if (dir.empty()) GTEST_SKIP() << "SingleStepTests 8086 vectors not present (set RCSIM_SST_DIR)";
    WorstClocks worst(WaitBounds{0, 0, 0, 0});
    Runner runner;
    const std::vector<std::string> files = collect({dir});
    std::size_t checked = 0, over = 0;
    double tightest = 0;
    std::string tightest_at, first_over;
    for (std::size_t f = GetParam(); f < files.size(); f += kShards) {
        const std::string& path = files[f];
        const nlohmann::json all = nlohmann::json::parse(read_text(path));
        const std::vector<rcsim::i8086::sst::Test> tests = Runner::convert(all, path);
        // (only DIV/IDIV and AAM can divide by zero; INT 0 reads the same vector on purpose)
        const std::string stem = path.substr(path.find_last_of('/') + 1);
        const bool divides = stem.rfind("F6.6", 0) == 0 || stem.rfind("F6.7", 0) == 0 ||
                             stem.rfind("F7.6", 0) == 0 || stem.rfind("F7.7", 0) == 0 || stem.rfind("D4", 0) == 0;
        const std::vector<Runner::Timing> ours = runner.timing_per_test(tests, false);
        for (std::size_t i = 0; i < tests.size(); ++i) {
            if (divides && divide_error(ours[i])) continue;
            const std::vector<std::uint8_t> b = all[i].at("bytes").get<std::vector<std::uint8_t>>();
            const unsigned captured = static_cast<unsigned>(tests[i].cycles->size());
            const unsigned limit = bound(worst, b, tests[i].init.r[rcsim::i8086::CX], tests[i].init.ip);
            ++checked;
            const double ratio = double(captured) / limit;
            if (ratio > tightest) {
                tightest = ratio;
                tightest_at = stem + " " + tests[i].name;
            }
            if (captured > limit && over++ == 0)
                first_over = stem + " test " + std::to_string(i) + " (" + tests[i].name + "): " +
                             std::to_string(captured) + " clocks, bound " + std::to_string(limit);
        }
    }
    EXPECT_EQ(over, 0u) << "first: " << first_over << "; worst ratio " << tightest << " at " << tightest_at;
    EXPECT_GT(checked, 7500u); // ~80 files of 100 vectors each per shard (less the divide errors)
    std::cout << "shard " << GetParam() << ": " << checked << " vectors, worst ratio captured/bound " << tightest
              << " (" << tightest_at << ")\n";
}

INSTANTIATE_TEST_SUITE_P(Shards, WorstClocksVectors, ::testing::Range(0u, kShards));

// Known answers: the iAPX 86/88 User's Manual's clock table gives each form's clocks without
// wait states (a range where the time depends on the operands: the bound is at least its top);
// every wait state of a bus cycle the form must run adds one clock.
TEST(WorstClocks, AtLeastTheDatasheetFigures) {
    WorstClocks w(WaitBounds{0, 0, 0, 0});
    EXPECT_GE(bound(w, {0x8A, 0xC3}), 2u);             // MOV AL,BL: 2
    EXPECT_GE(bound(w, {0xF7, 0xE3}), 133u);           // MUL BX: 118-133
    EXPECT_GE(bound(w, {0xF6, 0xE3}), 77u);            // MUL BL: 70-77
    EXPECT_GE(bound(w, {0xF7, 0xEB}), 154u);           // IMUL BX: 128-154
    EXPECT_GE(bound(w, {0xF7, 0xF3}), 162u);           // DIV BX: 144-162
    EXPECT_GE(bound(w, {0xF6, 0xF3}), 90u);            // DIV BL: 80-90
    EXPECT_GE(bound(w, {0xF7, 0xFB}), 184u);           // IDIV BX: 165-184
    EXPECT_GE(bound(w, {0xD4, 0x0A}), 83u);            // AAM: 83
    EXPECT_GE(bound(w, {0xE4, 0x60}), 10u);            // IN AL,60h: 10
    EXPECT_GE(bound(w, {0xD3, 0xE0}, 10), 8u + 4 * 10); // SHL AX,CL: 8 + 4/bit, CL up to 10
    EXPECT_GE(bound(w, {0xE2, 0xFE}), 17u);            // LOOP: 17 taken, 5 not
    EXPECT_GE(bound(w, {0x74, 0x10}), 16u);            // JZ: 16 taken, 4 not
    EXPECT_GE(bound(w, {0xCD, 0x21}), 51u);            // INT 21h: 51
    EXPECT_GE(bound(w, {0xF3, 0xA5}, 100), 9u + 17 * 100); // REP MOVSW: 9 + 17/rep, CX up to 100
    EXPECT_GE(w.interrupt_entry(), 61u);               // INTR: 61 (two INTA cycles and the entry)
}

TEST(WorstClocks, TheCountsAndShiftsGrowWithCxMax) {
    WorstClocks w(WaitBounds{0, 0, 0, 0});
    // 17 clocks per MOVSW element, 4 per bit shifted: more CX, more time by at least those.
    EXPECT_GE(bound(w, {0xF3, 0xA5}, 200), bound(w, {0xF3, 0xA5}, 100) + 17 * 100);
    EXPECT_GE(bound(w, {0xD3, 0xE0}, 20), bound(w, {0xD3, 0xE0}, 10) + 4 * 10);
    // A shift counts CL alone: a CX above 255 allows CL = 255 and no more.
    EXPECT_EQ(bound(w, {0xD3, 0xE0}, 0x1234), bound(w, {0xD3, 0xE0}, 255));
    // Without REP the count is not CX's.
    EXPECT_EQ(bound(w, {0xA5}, 0), bound(w, {0xA5}, 0xFFFF));
}

TEST(WorstClocks, EachWaitStateRaisesTheBoundOfTheCyclesItHolds) {
    WorstClocks none(WaitBounds{0, 0, 0, 0}), io(WaitBounds{0, 0, 1, 0}), data(WaitBounds{0, 1, 0, 0}),
        code(WaitBounds{1, 0, 0, 0}), inta(WaitBounds{0, 0, 0, 1});
    // IN AL,60h: one I/O read, so one clock per I/O wait state (10 + 1 with one).
    EXPECT_GE(bound(io, {0xE4, 0x60}), 11u);
    EXPECT_GE(bound(io, {0xE4, 0x60}), bound(none, {0xE4, 0x60}) + 1);
    // MOV [BX],AX: one or two data writes (odd address): one more clock at least.
    EXPECT_GE(bound(data, {0x89, 0x07}), bound(none, {0x89, 0x07}) + 1);
    // REP MOVSW with 100 words: a read and a write each, every one a wait state later.
    EXPECT_GE(bound(data, {0xF3, 0xA5}, 100), bound(none, {0xF3, 0xA5}, 100) + 2 * 100);
    // A far jump refetches its target: a code wait state shows.
    EXPECT_GT(bound(code, {0xEA, 0x00, 0x01, 0x00, 0x20}), bound(none, {0xEA, 0x00, 0x01, 0x00, 0x20}));
    // The entry: two INTA cycles, so two clocks at least.
    EXPECT_GE(inta.interrupt_entry(), none.interrupt_entry() + 2);
    EXPECT_GE(data.interrupt_entry(), none.interrupt_entry() + 5); // 3 pushes, 2 vector reads
}

TEST(WorstClocks, OperandValuesAlignmentAndFlagsAreTakenAtTheirWorst) {
    WorstClocks w(WaitBounds{0, 0, 0, 0});
    // CWD takes a clock more for a negative AX (the vectors show 5 and 6).
    EXPECT_GE(bound(w, {0x99}), 6u);
    // A word at an odd address takes two bus cycles: MOV AX,[BX] and PUSH are bounded as if odd,
    // so at least a bus cycle (4 clocks) above a byte access of the same form.
    EXPECT_GE(bound(w, {0x8B, 0x07}), bound(w, {0x8A, 0x07}) + 4);
    // A taken conditional jump is the worst of the two: as JMP short at the least.
    EXPECT_GE(bound(w, {0x7F, 0x10}), bound(w, {0xEB, 0x10}));
    // The cache answers by bytes, IP parity and cx_max: the same question, the same answer.
    EXPECT_EQ(bound(w, {0xEB, 0x10}, 0, 0x100), bound(w, {0xEB, 0x10}, 0, 0x200));
}

TEST(WorstClocks, TheBytesAfterTheInstructionDoNotChangeItsBound) {
    // The bound is the instruction's time, whatever follows it (the next instruction's bytes, as
    // the scenario test passes them): a preamble that flushes the queue (JMP $+2, CALL $+3) must
    // run the instruction itself after it, not the bytes a fetch made before the flush.
    WorstClocks w(kBoardWaits);
    EXPECT_EQ(bound(w, {0xFB, 0xC3, 0x00, 0x00}), bound(w, {0xFB}));             // STI; RET
    EXPECT_EQ(bound(w, {0x8B, 0xC3, 0xF7, 0xF3}), bound(w, {0x8B, 0xC3}));       // MOV AX,BX; DIV BX
    EXPECT_EQ(bound(w, {0x90, 0xCD, 0x21, 0x90}, 0xFFFF, 0x101), bound(w, {0x90}, 0xFFFF, 0x101)); // NOP; INT 21h
}

TEST(WorstClocks, ARunThatDividesByZeroIsNotTheInstructionsTime) {
    // With 10 wait states per data cycle the divide error's entry (two vector reads, three
    // pushes: 50 clocks of waits) is far longer than any DIV BL that completes (no data cycle:
    // 80-90 clocks). DIV AH always faults (AH / AH does not fit): its bound is what the fault
    // takes, the only time it has. DIV BL faults for BL = 0 but its bound leaves those runs out.
    WorstClocks w(WaitBounds{0, 10, 0, 0});
    const unsigned fault_only = bound(w, {0xF6, 0xF4});
    EXPECT_GE(fault_only, 90u + 5 * 10);
    EXPECT_LT(bound(w, {0xF6, 0xF3}), 90u + 5 * 10);
    EXPECT_GE(bound(w, {0xF6, 0xF3}), 90u);
}

namespace {

const WaitBounds kBoard = kBoardWaits;

/// `n` copies of the instruction `b` laid end to end from `ip`, as sequence() pieces (which point
/// into `b`).
std::vector<Piece> line(const std::vector<std::uint8_t>& b, unsigned n, std::uint16_t ip = 0x100) {
    std::vector<Piece> out;
    for (unsigned i = 0; i < n; ++i)
        out.push_back(Piece{b.data(), static_cast<unsigned>(b.size()), static_cast<std::uint16_t>(ip + i * b.size())});
    return out;
}

unsigned sum_of_bounds(WorstClocks& w, const std::vector<Piece>& pieces) {
    unsigned sum = 0;
    for (const Piece& p : pieces) sum += w.instruction(p.bytes, p.length, p.ip);
    return sum;
}

} // namespace

TEST(WorstClocksSequence, OnePieceIsTheInstructionsBoundOnTheShippedFirmware) {
    // Every instruction form the firmware ROM holds (decoded from its start, its code at offset
    // = IP), each distinct bytes-and-IP-parity once: the sequence of it alone is its bound.
    const std::vector<std::uint8_t> rom = rcsim::test::slurp_bytes(RCSIM_COMM_FW_ROM);
    ASSERT_GE(rom.size(), 0x1000u);
    WorstClocks single(kBoard), seq(kBoard);
    std::set<std::string> seen;
    std::size_t compared = 0, left = 0;
    for (unsigned at = 0; at + 16 < rom.size() && compared < 400;) {
        const rcsim::i8086::Decoded d = rcsim::i8086::decode(&rom[at], 16);
        const unsigned n = d.length ? d.length : 1;
        const std::uint16_t ip = static_cast<std::uint16_t>(at);
        const std::string key = std::string(rom.begin() + at, rom.begin() + at + n) + char(ip & 1);
        if (d.length && seen.insert(key).second) {
            if (!WorstClocks::sequenceable(&rom[at], n, ip)) ++left;
            else {
                ++compared;
                EXPECT_EQ(seq.sequence({Piece{&rom[at], n, ip}}), single.instruction(&rom[at], n, ip))
                    << "at " << std::hex << at << " " << rcsim::i8086::mnemonic(&rom[at], n);
            }
        }
        at += n;
    }
    EXPECT_EQ(compared, 400u);
    std::cout << compared << " instructions of the ROM compared, " << left << " left to instruction()\n";
    EXPECT_GT(left, 20u); // (the ROM's Jcc, CALL through memory, RET, REP MOVS ... are left out)
}

TEST(WorstClocksSequence, AFewInstructionsLieBetweenTheManualsSumAndTheirBoundsSum) {
    // The manual's figures assume the instruction queued and no wait state: NOP 3, MOV reg,reg 2,
    // MOV reg,mem 8 + EA (base + displacement: 9) + 4 for a word at an odd address, which the
    // bound takes at its worst alignment.
    struct Form {
        std::vector<std::uint8_t> bytes;
        unsigned manual;
    };
    const Form forms[] = {{{0x90}, 3}, {{0x8B, 0xC3}, 2}, {{0x8B, 0x47, 0x02}, 8 + 9 + 4}};
    for (const WaitBounds& waits : {WaitBounds{0, 0, 0, 0}, kBoard}) {
        WorstClocks w(waits);
        for (const Form& f : forms)
            for (unsigned n = 2; n <= 8; ++n) {
                const std::vector<Piece> p = line(f.bytes, n);
                const unsigned b = w.sequence(p);
                EXPECT_GE(b, n * f.manual) << n << " x " << rcsim::i8086::mnemonic(f.bytes.data(), static_cast<unsigned>(f.bytes.size()));
                EXPECT_LE(b, sum_of_bounds(w, p)) << n << " x " << rcsim::i8086::mnemonic(f.bytes.data(), static_cast<unsigned>(f.bytes.size()));
            }
    }
}

TEST(WorstClocksSequence, ALongStraightLineIsBoundedBelowTheSumOfItsInstructions) {
    // Ten MOV AX,[BX+2]: each alone is bounded with its worst queue (empty, refilled through the
    // ROM's wait state); in a line the queue fills during each one's 21 clocks of execution.
    WorstClocks w(kBoard);
    const std::vector<std::uint8_t> mov{0x8B, 0x47, 0x02};
    const std::vector<Piece> p = line(mov, 10);
    const unsigned b = w.sequence(p), sum = sum_of_bounds(w, p);
    EXPECT_LT(b, sum);
    EXPECT_GE(b, 10u * (8 + 9 + 4));
    std::cout << "10 x MOV AX,[BX+2] at the board's wait states: sequence " << b << ", sum of bounds " << sum << "\n";
}

TEST(WorstClocksSequence, DirectTransfersTakeTheNextPieceAtTheirTarget) {
    // MOV AX,[BX+2]; JMP short +4; (target) CALL near +0 (the next instruction); JMP far to
    // 5000:0200; (there) NOP. The manual: 21, 15, 19, 15, 3.
    const std::uint8_t mov[] = {0x8B, 0x47, 0x02}, jmp[] = {0xEB, 0x04}, call[] = {0xE8, 0x00, 0x00},
                       far[] = {0xEA, 0x00, 0x02, 0x00, 0x50}, nop[] = {0x90};
    const std::vector<Piece> p{{mov, 3, 0x100}, {jmp, 2, 0x103}, {call, 3, 0x109}, {far, 5, 0x10C}, {nop, 1, 0x200}};
    WorstClocks w(kBoard);
    const unsigned b = w.sequence(p);
    EXPECT_GE(b, 21u + 15 + 19 + 15 + 3);
    EXPECT_LE(b, sum_of_bounds(w, p));
    // A piece that is not where the previous one goes is refused.
    std::vector<Piece> wrong = p;
    wrong[2].ip = 0x105;
    EXPECT_THROW(w.sequence(wrong), std::invalid_argument);
}

TEST(WorstClocksSequence, TheFormsItCannotBoundAreRefused) {
    WorstClocks w(kBoard);
    const std::vector<std::vector<std::uint8_t>> refused{
        {0x74, 0x10},       // JZ (branch() bounds a line that ends in it)
        {0xE2, 0xFE},       // LOOP
        {0xE3, 0x10},       // JCXZ
        {0xFF, 0xD3},       // CALL BX
        {0xFF, 0x27},       // JMP [BX]
        {0xFF, 0x1F},       // CALL FAR [BX]
        {0xCD, 0x21},       // INT 21h
        {0xCE},             // INTO
        {0xF4},             // HLT
        {0xF3, 0xA4},       // REP MOVSB
        {0xD3, 0xE0},       // SHL AX,CL
        {0xF6, 0xE3},       // MUL BL
        {0xF7, 0xFB},       // IDIV BX
        {0xD4, 0x0A},       // AAM
        {0xD5, 0x0A},       // AAD
    };
    const std::uint8_t nop[] = {0x90};
    for (const auto& b : refused) {
        const Piece p{b.data(), static_cast<unsigned>(b.size()), 0x100};
        EXPECT_FALSE(WorstClocks::sequenceable(p.bytes, p.length, p.ip)) << rcsim::i8086::mnemonic(b.data(), static_cast<unsigned>(b.size()));
        EXPECT_THROW(w.sequence({p}), std::invalid_argument) << rcsim::i8086::mnemonic(b.data(), static_cast<unsigned>(b.size()));
        EXPECT_THROW(w.sequence({Piece{nop, 1, 0x0FF}, p}), std::invalid_argument); // (later in a line too)
    }
    // A return or IRET ends a line (a test below) but may not stand before another piece; a
    // conditional transfer is branch()'s, not sequence()'s, even last.
    for (const std::vector<std::uint8_t>& b : std::vector<std::vector<std::uint8_t>>{{0xC3}, {0xCA, 0x02, 0x00}, {0xCF}}) {
        EXPECT_FALSE(WorstClocks::sequenceable(b.data(), static_cast<unsigned>(b.size()), 0x100));
        EXPECT_THROW(w.sequence({Piece{b.data(), static_cast<unsigned>(b.size()), 0x100},
                                 Piece{nop, 1, static_cast<std::uint16_t>(0x100 + b.size())}}),
                     std::invalid_argument);
    }
    // Nothing, bytes that end inside the instruction, two pieces with other bytes at one address.
    const std::uint8_t mov[] = {0x8B, 0x47, 0x02}, back[] = {0xEB, 0xFD}, inc[] = {0x40};
    EXPECT_THROW(w.sequence({}), std::invalid_argument);
    EXPECT_THROW(w.sequence({Piece{mov, 2, 0x100}}), std::invalid_argument);
    EXPECT_THROW(w.sequence({Piece{inc, 1, 0x0FF}, Piece{back, 2, 0x100}, Piece{nop, 1, 0x0FF}}), std::invalid_argument);
    // ... which the same line with its real bytes at 00FF passes.
    EXPECT_GT(w.sequence({Piece{inc, 1, 0x0FF}, Piece{back, 2, 0x100}, Piece{inc, 1, 0x0FF}}), 0u);
    // The forms a line can hold are taken: a string instruction without REP, a shift by 1, POPF.
    for (const std::vector<std::uint8_t>& b : std::vector<std::vector<std::uint8_t>>{{0xA4}, {0xD1, 0xE0}, {0x9D}})
        EXPECT_TRUE(WorstClocks::sequenceable(b.data(), static_cast<unsigned>(b.size()), 0x100));
}

TEST(WorstClocksSequence, AReturnEndsALine) {
    // Alone, a return's line is its instruction() bound (both parities of the address it pops:
    // the stack's fill, FFFF and 0000), at both parities of its own IP.
    WorstClocks w(kBoard), single(kBoard);
    const std::vector<std::vector<std::uint8_t>> returns{{0xC3}, {0xC2, 0x04, 0x00}, {0xCB}, {0xCA, 0x02, 0x00}, {0xCF},
                                                         {0xC1}, {0xC0, 0x02, 0x00}, {0xC9}, {0xC8, 0x02, 0x00}};
    for (const auto& b : returns)
        for (std::uint16_t ip : {0x100, 0x101}) {
            const unsigned n = static_cast<unsigned>(b.size());
            EXPECT_EQ(w.sequence({Piece{b.data(), n, ip}}), single.instruction(b.data(), n, ip))
                << rcsim::i8086::mnemonic(b.data(), n) << " at " << ip;
        }
    // MOV AX,[BX+2]; RET: the manual's 21 + 8 (RET 8, RETF 18, IRET 24) at the least, the sum of
    // the two bounds at the most.
    const std::uint8_t mov[] = {0x8B, 0x47, 0x02};
    const std::pair<std::vector<std::uint8_t>, unsigned> ends[] = {{{0xC3}, 8}, {{0xCB}, 18}, {{0xCF}, 24}};
    for (const auto& [b, manual] : ends) {
        const std::vector<Piece> p{{mov, 3, 0x100}, {b.data(), 1, 0x103}};
        EXPECT_GE(w.sequence(p), 21u + manual);
        EXPECT_LE(w.sequence(p), sum_of_bounds(w, p));
    }
}

namespace {

/// Whether a SingleStepTests file holds a conditional transfer: 70-7F, its aliases 60-6F, E0-E3.
bool branch_file(const std::string& stem) {
    const unsigned op = static_cast<unsigned>(std::stoul(stem.substr(0, 2), nullptr, 16));
    return (op >= 0x60 && op <= 0x7F) || (op >= 0xE0 && op <= 0xE3);
}

} // namespace

TEST(WorstClocksBranch, NoVectorTakesMoreThanItsOutcomesBound) {
    // Every captured vector of a conditional transfer takes at most branch()'s bound of the
    // outcome it took: its final IP is the target (taken) or the next instruction (not taken).
    using namespace rcsim::i8086::sst;
    const std::string dir = rcsim::test::sst_dir();
    if (dir.empty()) GTEST_SKIP() << "SingleStepTests 8086 vectors not present (set RCSIM_SST_DIR)";
    WorstClocks worst(WaitBounds{0, 0, 0, 0});
    std::size_t taken = 0, not_taken = 0, over = 0, taken_over_not = 0;
    double tightest_taken = 0, tightest_not = 0;
    std::string first_over;
    for (const std::string& path : collect({dir})) {
        const std::string stem = path.substr(path.find_last_of('/') + 1);
        if (!branch_file(stem)) continue;
        const nlohmann::json all = nlohmann::json::parse(read_text(path));
        const std::vector<rcsim::i8086::sst::Test> tests = Runner::convert(all, path);
        for (std::size_t i = 0; i < tests.size(); ++i) {
            const std::vector<std::uint8_t> b = all[i].at("bytes").get<std::vector<std::uint8_t>>();
            const unsigned n = static_cast<unsigned>(b.size());
            const std::uint16_t ip = tests[i].init.ip;
            const rcsim::i8086::Decoded d = rcsim::i8086::decode(b.data(), n);
            ASSERT_EQ(d.flow, rcsim::i8086::Flow::branch) << stem << " " << tests[i].name;
            const std::uint16_t target = rcsim::i8086::direct_target(b.data(), d, ip)->ip;
            const std::uint16_t next = static_cast<std::uint16_t>(ip + d.length);
            if (target == next) continue; // (a zero displacement: the final IP does not say which)
            // (a vector lists the registers it changed: no final IP, the jump to itself)
            const std::uint16_t final_ip = tests[i].fin_present[12] ? tests[i].fin[12] : ip;
            ASSERT_TRUE(final_ip == target || final_ip == next) << stem << " " << tests[i].name;
            const bool was_taken = final_ip == target;
            const rcsim::i8086::Outcomes o = worst.branch({Piece{b.data(), n, ip}});
            const unsigned limit = was_taken ? o.taken : o.not_taken;
            const unsigned captured = static_cast<unsigned>(tests[i].cycles->size());
            ++(was_taken ? taken : not_taken);
            if (was_taken && captured > o.not_taken) ++taken_over_not; // (the check can fail)
            double& tightest = was_taken ? tightest_taken : tightest_not;
            tightest = std::max(tightest, double(captured) / limit);
            if (captured > limit && over++ == 0)
                first_over = stem + " " + tests[i].name + (was_taken ? " (taken): " : " (not taken): ") +
                             std::to_string(captured) + " clocks, bound " + std::to_string(limit);
        }
    }
    EXPECT_EQ(over, 0u) << "first: " << first_over;
    EXPECT_GT(taken, 1000u);
    EXPECT_GT(not_taken, 1000u);
    // The check can fail: the taken vectors exceed the bound of the other outcome.
    EXPECT_GT(taken_over_not, taken * 9 / 10);
    std::cout << taken << " taken and " << not_taken << " not taken vectors; tightest captured/bound " << tightest_taken
              << " taken, " << tightest_not << " not taken\n";
}

TEST(WorstClocksBranch, EachOutcomeHoldsTheManualsFigureAndTheLargerIsTheInstructionsBound) {
    // The iAPX 86/88 User's Manual, taken / not taken: Jcc 16 / 4, LOOP 17 / 5, LOOPE 18 / 6,
    // LOOPNE 19 / 5, JCXZ 18 / 6. The taken outcome refills the queue from the target: the
    // bound of a taken Jcc is above its fall-through's. One piece's larger outcome is what
    // instruction() gives the same bytes.
    struct Form {
        std::vector<std::uint8_t> bytes;
        unsigned taken, not_taken;
    };
    const std::vector<Form> forms{{{0x74, 0x10}, 16, 4}, {{0x7F, 0xF0}, 16, 4}, {{0x65, 0x10}, 16, 4},
                                  {{0xE2, 0xFE}, 17, 5}, {{0xE1, 0x10}, 18, 6}, {{0xE0, 0x10}, 19, 5},
                                  {{0xE3, 0x10}, 18, 6}};
    for (const WaitBounds& waits : {WaitBounds{0, 0, 0, 0}, kBoard}) {
        WorstClocks w(waits), single(waits);
        for (const Form& f : forms)
            for (std::uint16_t ip : {0x100, 0x101}) {
                const unsigned n = static_cast<unsigned>(f.bytes.size());
                const std::string what = rcsim::i8086::mnemonic(f.bytes.data(), n) + " at " + std::to_string(ip);
                const rcsim::i8086::Outcomes o = w.branch({Piece{f.bytes.data(), n, ip}});
                EXPECT_GE(o.taken, f.taken) << what;
                EXPECT_GE(o.not_taken, f.not_taken) << what;
                EXPECT_GT(o.taken, o.not_taken) << what;
                EXPECT_EQ(std::max(o.taken, o.not_taken), single.instruction(f.bytes.data(), n, ip)) << what;
            }
    }
    // Every Jcc and alias, every LOOP form, JCXZ: the same equality at the board's wait states.
    WorstClocks w(kBoard), single(kBoard);
    for (unsigned op = 0x60; op <= 0xE3; op = op == 0x7F ? 0xE0 : op + 1) {
        const std::uint8_t b[] = {static_cast<std::uint8_t>(op), 0x20};
        const rcsim::i8086::Outcomes o = w.branch({Piece{b, 2, 0x100}});
        EXPECT_EQ(std::max(o.taken, o.not_taken), single.instruction(b, 2, 0x100)) << std::hex << op;
        EXPECT_GT(o.taken, o.not_taken) << std::hex << op;
    }
}

TEST(WorstClocksBranch, ACompareChainIsBoundedPerEdge) {
    // CMP AL,5; JZ +10 (a handler's dispatch): the manual's 4 + 16 taken, 4 + 4 not taken; each
    // outcome at most the sum of the two instructions' bounds (which take the jump taken).
    WorstClocks w(kBoard);
    const std::uint8_t cmp[] = {0x3C, 0x05}, jz[] = {0x74, 0x0A};
    const std::vector<Piece> p{{cmp, 2, 0x100}, {jz, 2, 0x102}};
    const rcsim::i8086::Outcomes o = w.branch(p);
    const unsigned sum = sum_of_bounds(w, p);
    EXPECT_GE(o.taken, 4u + 16);
    EXPECT_GE(o.not_taken, 4u + 4);
    EXPECT_LE(o.taken, sum);
    EXPECT_LT(o.not_taken, o.taken);
    std::cout << "CMP AL,5; JZ at the board's wait states: taken " << o.taken << ", not taken " << o.not_taken
              << ", sum of the instructions' bounds " << sum << "\n";
}

TEST(WorstClocksBranch, OnlyALineEndingInAConditionalTransferIsTaken) {
    WorstClocks w(kBoard);
    const std::uint8_t nop[] = {0x90}, jz[] = {0x74, 0x0A}, ret[] = {0xC3}, mul[] = {0xF6, 0xE3};
    EXPECT_THROW(w.branch({}), std::invalid_argument);
    EXPECT_THROW(w.branch({Piece{nop, 1, 0x100}}), std::invalid_argument);                        // no branch
    EXPECT_THROW(w.branch({Piece{jz, 2, 0x100}, Piece{nop, 1, 0x102}}), std::invalid_argument);   // not last
    EXPECT_THROW(w.branch({Piece{ret, 1, 0x100}}), std::invalid_argument);                        // a return
    EXPECT_THROW(w.branch({Piece{mul, 2, 0x100}, Piece{jz, 2, 0x102}}), std::invalid_argument);   // MUL before
    EXPECT_THROW(w.branch({Piece{nop, 1, 0x100}, Piece{jz, 2, 0x102}}), std::invalid_argument);   // not where NOP goes
    EXPECT_THROW(w.branch({Piece{jz, 1, 0x100}}), std::invalid_argument);                         // cut short
    EXPECT_GT(w.branch({Piece{nop, 1, 0x100}, Piece{jz, 2, 0x101}}).not_taken, 0u);
}
