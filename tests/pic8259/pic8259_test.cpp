// 8259A behaviour tests: the INTA sequence, triggering, every OCW2 command, OCW3, ICW1 side
// effects, and the nine known-tricky behaviours of pic8259/README.md (marked "tricky n").
#include "tests/pic8259/pic_with_cpu.h"
#include "tests/support/sc_test.h"

using rcsim::Pic8259;
using rcsim::test::PicWithCpu;

namespace {

void run(PicWithCpu& tb, std::function<void()> body) {
    tb.body = std::move(body);
    sc_core::sc_start(); // PicWithCpu's body is a checked thread: a stuck one fails the test
}

} // namespace

// ---------------------------------------------------------------------------------------------
// INTA sequence

// Tricky 1: the IS bit is set (and IRR cleared) by the FIRST INTA, the vector comes on the second.
TEST(Pic8259, FirstIntaSetsIsrSecondDrivesVector) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        EXPECT_FALSE(tb.intr.read());
        tb.set_ir(2, true);
        EXPECT_TRUE(tb.intr.read());
        EXPECT_EQ(tb.pic.irr(), 0x04);

        EXPECT_EQ(tb.inta_cycle(), 0xFF) << "the 8259A does not drive the bus in the first INTA";
        EXPECT_EQ(tb.pic.isr(), 0x04);
        EXPECT_EQ(tb.pic.irr(), 0x00);
        EXPECT_FALSE(tb.intr.read()) << "IR2 in service blocks itself";

        EXPECT_EQ(tb.inta_cycle(), 0x22);
        EXPECT_EQ(tb.pic.isr(), 0x04) << "no AEOI: IS stays set until an EOI";
        ASSERT_EQ(tb.inta_log.size(), 2u);
        EXPECT_EQ(tb.inta_log[0].cycle, 1u);
        EXPECT_EQ(tb.inta_log[0].level, 2u);
        EXPECT_EQ(tb.inta_log[1].cycle, 2u);
        EXPECT_EQ(tb.inta_log[1].data, 0x22);
        EXPECT_EQ(tb.pic.acks(2), 1u);
        EXPECT_EQ(tb.pic.last_ack_level(), 2);
        EXPECT_EQ(tb.pic.last_ack_time(), tb.inta_log[0].time);
    });
}

// The resolver's choice is frozen at the first INTA, not when INT rose.
TEST(Pic8259, HigherRequestBeforeFirstIntaWins) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(5, true);
        EXPECT_TRUE(tb.intr.read());
        tb.set_ir(1, true); // arrives while INT is already up
        EXPECT_EQ(tb.inta_pair(), 0x21);
        EXPECT_EQ(tb.pic.isr(), 0x02);
        EXPECT_EQ(tb.pic.irr(), 0x20);
    });
}

// Lines that change in the same instant are decided on once, after all have settled.
TEST(Pic8259, SimultaneousRequestsSettleBeforeDecision) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.ir[6].write(true);
        tb.ir[3].write(true);
        tb.settle();
        EXPECT_EQ(tb.pic.pending_level(), 3);
        EXPECT_EQ(tb.inta_pair(), 0x23);
    });
}

TEST(Pic8259, AutoEoiClearsIsrAtEndOfSecondInta) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x48, 0x03); // AEOI, vector base 0x48
        tb.set_ir(4, true);
        tb.inta_cycle();
        EXPECT_EQ(tb.pic.isr(), 0x10) << "AEOI still sets ISR at the first INTA";
        EXPECT_EQ(tb.inta_cycle(), 0x4C);
        EXPECT_EQ(tb.pic.isr(), 0x00);
        EXPECT_EQ(tb.pic.lowest_priority(), 7u) << "AEOI without the rotate flag does not rotate";
    });
}

TEST(Pic8259, Icw2LowBitsIgnoredIn8086Mode) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x27);
        tb.set_ir(1, true);
        EXPECT_EQ(tb.inta_pair(), 0x21);
    });
}

// Tricky 2: a request gone before the first INTA gives the IR7 vector without setting ISR7.
TEST(Pic8259, SpuriousIr7WhenEdgeRequestDropsBeforeFirstInta) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(3, true);
        EXPECT_TRUE(tb.intr.read());
        tb.set_ir(3, false);
        EXPECT_FALSE(tb.intr.read());
        EXPECT_EQ(tb.pic.irr(), 0x00);
        EXPECT_EQ(tb.inta_pair(), 0x27);
        EXPECT_EQ(tb.pic.isr(), 0x00) << "ISR7 must not be set for a spurious interrupt";
        EXPECT_EQ(tb.pic.spurious_acks(), 1u);
        EXPECT_EQ(tb.pic.acks(7), 0u);
        ASSERT_EQ(tb.inta_log.size(), 2u);
        EXPECT_TRUE(tb.inta_log[0].spurious);
        EXPECT_EQ(tb.pic.last_ack_level(), 7);

        // A genuine IR7 gives the same vector but sets ISR7: that is how a handler tells them apart.
        tb.set_ir(7, true);
        EXPECT_EQ(tb.inta_pair(), 0x27);
        EXPECT_EQ(tb.pic.isr(), 0x80);
        EXPECT_EQ(tb.pic.spurious_acks(), 1u);
    });
}

TEST(Pic8259, SpuriousIr7InLevelModeAndWithAutoEoi) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x1B, 0x20, 0x03); // level triggered, AEOI
        tb.set_ir(5, true);
        tb.out(false, 0x0C);
        EXPECT_EQ(tb.in(false), 0x85); // a poll puts IR5 in service without AEOI
        tb.set_ir(5, false);
        tb.set_ir(1, true);
        EXPECT_TRUE(tb.intr.read());
        tb.set_ir(1, false);
        EXPECT_FALSE(tb.intr.read());
        EXPECT_EQ(tb.inta_pair(), 0x27);
        EXPECT_EQ(tb.pic.spurious_acks(), 1u);
        EXPECT_EQ(tb.pic.isr(), 0x20) << "neither ISR7 set nor IS5 cleared by the AEOI of a spurious INTA";
    });
}

// Masking a level while INT is up drops INT; an INTA that comes anyway is spurious (ao486 #122).
TEST(Pic8259, MaskingWhileIntAssertedDropsIntAndGivesSpurious) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(4, true);
        EXPECT_TRUE(tb.intr.read());
        tb.out(true, 0x10);
        EXPECT_FALSE(tb.intr.read());
        EXPECT_EQ(tb.inta_pair(), 0x27);
        EXPECT_EQ(tb.pic.isr(), 0x00);
        tb.out(true, 0x00); // unmask: IR4 is still latched and high, so it requests again
        EXPECT_TRUE(tb.intr.read());
        EXPECT_EQ(tb.inta_pair(), 0x24);
    });
}

// ---------------------------------------------------------------------------------------------
// Triggering

// Tricky 3: edge lock-out; the line has to go low before it can request again.
TEST(Pic8259, EdgeLockoutRearmsOnlyAfterLineGoesLow) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(1, true);
        EXPECT_EQ(tb.inta_pair(), 0x21);
        tb.out(false, 0x20); // EOI with the line still high
        EXPECT_EQ(tb.pic.isr(), 0x00);
        EXPECT_EQ(tb.pic.irr(), 0x00);
        EXPECT_FALSE(tb.intr.read()) << "a level still high after the acknowledge is no new request";
        tb.set_ir(1, false);
        EXPECT_FALSE(tb.intr.read());
        tb.set_ir(1, true);
        EXPECT_TRUE(tb.intr.read());
        EXPECT_EQ(tb.inta_pair(), 0x21);
    });
}

TEST(Pic8259, EdgeWhileInServiceIsHeldUntilEoi) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(2, true);
        tb.inta_pair();
        tb.set_ir(2, false);
        tb.set_ir(2, true); // new edge while IR2 is in service
        EXPECT_EQ(tb.pic.irr(), 0x04);
        EXPECT_FALSE(tb.intr.read());
        tb.out(false, 0x20);
        EXPECT_TRUE(tb.intr.read());
        EXPECT_EQ(tb.inta_pair(), 0x22);
        EXPECT_EQ(tb.pic.acks(2), 2u);
    });
}

TEST(Pic8259, LevelModeRequestsAgainAfterEoiWhileHigh) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x1B);
        EXPECT_TRUE(tb.pic.level_triggered());
        tb.set_ir(1, true);
        EXPECT_EQ(tb.inta_pair(), 0x21);
        EXPECT_EQ(tb.pic.irr(), 0x02) << "in level mode IRR follows the pin";
        EXPECT_FALSE(tb.intr.read());
        tb.out(false, 0x20);
        EXPECT_TRUE(tb.intr.read()) << "line still high after EOI: another interrupt";
        EXPECT_EQ(tb.inta_pair(), 0x21);
        tb.set_ir(1, false);
        tb.out(false, 0x20);
        EXPECT_FALSE(tb.intr.read());
        EXPECT_EQ(tb.pic.irr(), 0x00);
    });
}

// A line already high when the edge-mode chip is initialised is no request (edge latch cleared).
TEST(Pic8259, LineHighAtIcw1IsNoEdgeRequest) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.set_ir(5, true);
        tb.init();
        EXPECT_EQ(tb.pic.irr(), 0x00);
        EXPECT_FALSE(tb.intr.read());
    });
}

// ---------------------------------------------------------------------------------------------
// Priority and OCW2

TEST(Pic8259, FullyNestedHigherInterruptsLowerAndSameOrLowerWait) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(4, true);
        EXPECT_EQ(tb.inta_pair(), 0x24);
        tb.set_ir(6, true);
        tb.set_ir(4, false);
        tb.set_ir(4, true);
        EXPECT_FALSE(tb.intr.read()) << "IR6 (lower) and IR4 (same) wait while IR4 is in service";
        tb.set_ir(2, true);
        EXPECT_TRUE(tb.intr.read()) << "IR2 (higher) interrupts the IR4 handler";
        EXPECT_EQ(tb.inta_pair(), 0x22);
        EXPECT_EQ(tb.pic.isr(), 0x14);
        tb.out(false, 0x20); // non-specific EOI ends IR2, the highest in service
        EXPECT_EQ(tb.pic.isr(), 0x10);
        EXPECT_FALSE(tb.intr.read());
        tb.out(false, 0x20);
        EXPECT_EQ(tb.pic.isr(), 0x00);
        EXPECT_EQ(tb.inta_pair(), 0x24) << "IR4 before IR6";
    });
}

TEST(Pic8259, Ocw2NonSpecificEoiClearsHighestPriorityIsBit) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.out(false, 0xC2); // IR3 highest ... IR2 lowest
        tb.set_ir(1, true);
        tb.inta_pair();
        tb.set_ir(5, true);
        tb.inta_pair();      // IR5 is above IR1 in this order, so it nests
        EXPECT_EQ(tb.pic.isr(), 0x22);
        tb.out(false, 0x20);
        EXPECT_EQ(tb.pic.isr(), 0x02) << "IR5 is the highest in service under the rotated order";
        EXPECT_EQ(tb.pic.lowest_priority(), 2u) << "a plain EOI does not rotate";
        EXPECT_EQ(tb.pic.eoi_commands(), 1u);
    });
}

TEST(Pic8259, Ocw2SpecificEoiClearsOnlyTheNamedLevel) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(5, true);
        tb.inta_pair();
        tb.set_ir(3, true);
        tb.inta_pair();
        EXPECT_EQ(tb.pic.isr(), 0x28);
        tb.out(false, 0x65); // specific EOI IR5 (not the highest)
        EXPECT_EQ(tb.pic.isr(), 0x08);
        EXPECT_EQ(tb.pic.lowest_priority(), 7u);
    });
}

TEST(Pic8259, Ocw2RotateOnNonSpecificEoiMakesServedLevelLowest) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(4, true);
        tb.inta_pair();
        EXPECT_EQ(tb.pic.lowest_priority(), 7u) << "no rotation at INTA";
        tb.out(false, 0xA0);
        EXPECT_EQ(tb.pic.isr(), 0x00);
        EXPECT_EQ(tb.pic.lowest_priority(), 4u) << "IR4 served -> IR5 highest ... IR4 lowest";
        tb.set_ir(3, true);
        tb.set_ir(6, true);
        EXPECT_EQ(tb.inta_pair(), 0x26) << "IR6 ranks above IR3 after the rotation";
        tb.out(false, 0xA0);
        EXPECT_EQ(tb.pic.lowest_priority(), 6u);
        // Nothing in service now (IR3 is only requesting): nothing to clear, no rotation.
        tb.out(false, 0xA0);
        EXPECT_EQ(tb.pic.lowest_priority(), 6u);
        EXPECT_EQ(tb.pic.irr(), 0x08);
    });
}

// Tricky 4 (AEOI rotation): with the flag set the rotation happens at the end of the second INTA.
TEST(Pic8259, Ocw2RotateInAutoEoiSetRotatesAtSecondInta) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x03);
        tb.out(false, 0x80);
        EXPECT_TRUE(tb.pic.rotate_in_auto_eoi());
        EXPECT_EQ(tb.pic.lowest_priority(), 7u) << "setting the flag rotates nothing by itself";
        tb.set_ir(0, true);
        tb.set_ir(1, true);
        tb.inta_cycle();
        EXPECT_EQ(tb.pic.lowest_priority(), 7u);
        EXPECT_EQ(tb.inta_cycle(), 0x20);
        EXPECT_EQ(tb.pic.lowest_priority(), 0u);
        tb.set_ir(0, false);
        tb.set_ir(0, true);
        EXPECT_EQ(tb.inta_pair(), 0x21) << "IR0 is now lowest: IR1 goes first";
        EXPECT_EQ(tb.inta_pair(), 0x20);
        EXPECT_EQ(tb.pic.lowest_priority(), 0u);
    });
}

// Tricky 4 (other half): rotate-on-EOI rotates at the EOI command, and AEOI mode without the flag
// does not rotate at all.
TEST(Pic8259, RotateOnEoiIsNotAutoEoiRotation) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x03); // AEOI, rotate flag clear
        tb.set_ir(2, true);
        tb.inta_pair();
        EXPECT_EQ(tb.pic.isr(), 0x00);
        EXPECT_EQ(tb.pic.lowest_priority(), 7u);
        tb.out(false, 0xA0); // nothing in service: no rotation
        EXPECT_EQ(tb.pic.lowest_priority(), 7u);
    });
}

// Tricky 5: OCW2 0x00 only clears the rotate-in-AEOI flag; it must not reset the priority order.
TEST(Pic8259, Ocw2RotateInAutoEoiClearKeepsPriority) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x03);
        tb.out(false, 0x80);
        tb.set_ir(5, true);
        tb.inta_pair();
        EXPECT_EQ(tb.pic.lowest_priority(), 5u);
        tb.out(false, 0x00);
        EXPECT_FALSE(tb.pic.rotate_in_auto_eoi());
        EXPECT_EQ(tb.pic.lowest_priority(), 5u);
        tb.set_ir(2, true);
        tb.set_ir(6, true);
        EXPECT_EQ(tb.inta_pair(), 0x26) << "IR6 is still highest after OCW2 0x00";
        EXPECT_EQ(tb.pic.lowest_priority(), 5u) << "and AEOI no longer rotates";
    });
}

TEST(Pic8259, Ocw2RotateOnSpecificEoi) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(5, true);
        tb.inta_pair();
        tb.set_ir(1, true);
        tb.inta_pair();
        EXPECT_EQ(tb.pic.isr(), 0x22);
        tb.out(false, 0xE5); // clear IS5, IR5 becomes lowest
        EXPECT_EQ(tb.pic.isr(), 0x02);
        EXPECT_EQ(tb.pic.lowest_priority(), 5u);
        tb.out(false, 0xE1);
        EXPECT_EQ(tb.pic.isr(), 0x00);
        EXPECT_EQ(tb.pic.lowest_priority(), 1u);
        EXPECT_EQ(tb.pic.eoi_commands(), 2u);
    });
}

TEST(Pic8259, Ocw2SetPriorityChangesOrderWithoutEoi) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(7, true);
        tb.inta_pair();
        tb.out(false, 0xC4); // IR4 lowest -> IR5 highest
        EXPECT_EQ(tb.pic.lowest_priority(), 4u);
        EXPECT_EQ(tb.pic.isr(), 0x80) << "set priority is no EOI";
        EXPECT_EQ(tb.pic.eoi_commands(), 0u);
        tb.set_ir(3, true);
        tb.set_ir(5, true);
        EXPECT_EQ(tb.inta_pair(), 0x25) << "IR5 highest: it nests above IR7";
        EXPECT_EQ(tb.pic.isr(), 0xA0);
        EXPECT_FALSE(tb.intr.read()) << "IR3 ranks below IR7 in this order";
    });
}

TEST(Pic8259, Ocw2NoOperationChangesNothing) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(3, true);
        tb.inta_pair();
        for (std::uint8_t l = 0; l < 8; ++l) tb.out(false, 0x40 | l);
        EXPECT_EQ(tb.pic.isr(), 0x08);
        EXPECT_EQ(tb.pic.lowest_priority(), 7u);
        EXPECT_EQ(tb.pic.eoi_commands(), 0u);
    });
}

// ---------------------------------------------------------------------------------------------
// Special mask mode

// Tricky 6: in SMM a masked in-service level no longer blocks lower levels, and a non-specific
// EOI skips IS bits that are masked.
TEST(Pic8259, SpecialMaskModeUnblocksLowerLevelsAndEoiException) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(1, true);
        tb.inta_pair();
        tb.set_ir(5, true);
        EXPECT_FALSE(tb.intr.read());
        tb.out(true, 0x02); // mask IR1 without SMM: still blocks
        EXPECT_FALSE(tb.intr.read()) << "without SMM a masked in-service level still blocks";
        tb.out(false, 0x68); // set SMM
        EXPECT_TRUE(tb.pic.special_mask_mode());
        EXPECT_TRUE(tb.intr.read()) << "SMM: masked IR1 in service no longer blocks IR5";
        EXPECT_EQ(tb.inta_pair(), 0x25);
        EXPECT_EQ(tb.pic.isr(), 0x22);
        tb.out(false, 0x20); // non-specific EOI: IS1 is masked, so IS5 is cleared
        EXPECT_EQ(tb.pic.isr(), 0x02);
        tb.out(false, 0x20); // nothing unmasked in service: nothing cleared
        EXPECT_EQ(tb.pic.isr(), 0x02);
        tb.out(false, 0x48); // reset SMM
        EXPECT_FALSE(tb.pic.special_mask_mode());
        tb.out(false, 0x20);
        EXPECT_EQ(tb.pic.isr(), 0x00);
    });
}

TEST(Pic8259, SpecialMaskModeUnmaskedInServiceStillBlocks) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.out(false, 0x68);
        tb.set_ir(2, true);
        tb.inta_pair();
        tb.set_ir(6, true);
        EXPECT_FALSE(tb.intr.read()) << "IR2 in service and not masked keeps blocking IR6";
        tb.out(true, 0x04);
        EXPECT_TRUE(tb.intr.read());
    });
}

// ---------------------------------------------------------------------------------------------
// OCW3, poll, register reads

TEST(Pic8259, RegisterReadsIrrIsrImr) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x01, 0xA5);
        EXPECT_EQ(tb.in(true), 0xA5);
        tb.set_ir(1, true);
        tb.set_ir(4, true);
        EXPECT_EQ(tb.in(false), 0x12) << "IRR shows masked requests too";
        tb.inta_pair();
        tb.out(false, 0x0B);
        EXPECT_EQ(tb.in(false), 0x02);
        EXPECT_EQ(tb.in(false), 0x02) << "the ISR selection persists";
        EXPECT_EQ(tb.in(true), 0xA5) << "A0=1 always reads IMR";
        tb.out(false, 0x0A);
        EXPECT_EQ(tb.in(false), 0x10);
    });
}

// Tricky 8: RR=0 leaves the read selection alone, ESMM=0 leaves special mask mode alone.
TEST(Pic8259, Ocw3NoChangeFields) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(3, true);
        tb.inta_pair();
        tb.set_ir(6, true);
        tb.out(false, 0x0B); // read ISR
        tb.out(false, 0x09); // RR=0, RIS=1: no change
        EXPECT_EQ(tb.in(false), 0x08);
        tb.out(false, 0x08); // RR=0, RIS=0: still no change
        EXPECT_EQ(tb.in(false), 0x08);
        tb.out(false, 0x0A);
        EXPECT_EQ(tb.in(false), 0x40);

        tb.out(false, 0x28); // ESMM=0, SMM=1: no change (stays off)
        EXPECT_FALSE(tb.pic.special_mask_mode());
        tb.out(false, 0x68);
        EXPECT_TRUE(tb.pic.special_mask_mode());
        tb.out(false, 0x08); // ESMM=0, SMM=0: no change (stays on)
        EXPECT_TRUE(tb.pic.special_mask_mode());
        tb.out(false, 0x48);
        EXPECT_FALSE(tb.pic.special_mask_mode());
    });
}

// Tricky 7: after OCW3 P=1 the next read is an acknowledge and returns I000 0Wwww.
TEST(Pic8259, PollReadActsAsAcknowledge) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(6, true);
        tb.set_ir(3, true);
        tb.out(false, 0x0C);
        EXPECT_TRUE(tb.pic.poll_pending());
        EXPECT_EQ(tb.in(false), 0x83);
        EXPECT_FALSE(tb.pic.poll_pending()) << "one poll, one read";
        EXPECT_EQ(tb.pic.isr(), 0x08);
        EXPECT_EQ(tb.pic.irr(), 0x40);
        EXPECT_EQ(tb.pic.acks(3), 1u);
        EXPECT_EQ(tb.in(false), 0x40) << "the next plain read is a register read (IRR)";
        tb.out(false, 0x20);
        tb.out(false, 0x0C);
        EXPECT_EQ(tb.in(true), 0x86) << "the poll read works with A0=1 as well";
        EXPECT_EQ(tb.pic.isr(), 0x40);
        tb.out(false, 0x20);
        tb.out(false, 0x0C);
        EXPECT_EQ(tb.in(false), 0x00) << "nothing pending: I=0";
        EXPECT_EQ(tb.pic.isr(), 0x00);
        EXPECT_EQ(tb.pic.polls(), 3u);
        EXPECT_TRUE(tb.inta_log.empty()) << "a poll is no INTA cycle";
    });
}

// P wins over RR/RIS given in the same OCW3; the register selection still takes effect after.
TEST(Pic8259, PollOverridesRegisterReadInSameOcw3) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init();
        tb.set_ir(2, true);
        tb.out(false, 0x0F); // P=1, RR=1, RIS=1
        EXPECT_EQ(tb.in(false), 0x82);
        EXPECT_EQ(tb.in(false), 0x04) << "then ISR is read";
    });
}

TEST(Pic8259, PollWithAutoEoiLeavesIsrSet) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x03);
        tb.set_ir(1, true);
        tb.out(false, 0x0C);
        EXPECT_EQ(tb.in(false), 0x81);
        EXPECT_EQ(tb.pic.isr(), 0x02) << "no second INTA, so no automatic EOI";
    });
}

// ---------------------------------------------------------------------------------------------
// Initialisation

// Tricky 9: ICW1 clears IMR (all unmasked!), the edge latches, special mask mode, the read
// selection and the rotation; OCW1 has to follow before interrupts are enabled.
TEST(Pic8259, Icw1SideEffects) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x01, 0xFF);
        tb.out(false, 0xC2);
        tb.out(false, 0x68);
        tb.out(false, 0x0B);
        tb.set_ir(6, true); // masked, but its edge is latched
        EXPECT_EQ(tb.pic.irr(), 0x40);
        tb.out(true, 0x00); // unmask to put IR6 in service
        tb.inta_pair();
        tb.out(true, 0xFF);
        tb.set_ir(1, true);
        EXPECT_EQ(tb.pic.irr(), 0x02);

        tb.out(false, 0x13); // ICW1
        EXPECT_EQ(tb.pic.init_state(), Pic8259::InitState::icw2);
        EXPECT_EQ(tb.pic.imr(), 0x00);
        EXPECT_EQ(tb.pic.irr(), 0x00) << "edge-sense latches cleared";
        EXPECT_EQ(tb.pic.lowest_priority(), 7u);
        EXPECT_FALSE(tb.pic.special_mask_mode());
        EXPECT_EQ(tb.pic.isr(), 0x40) << "ISR is not in the data sheet's list";
        EXPECT_EQ(tb.in(false), 0x00) << "status read selects IRR again";
        tb.set_ir(3, true);
        EXPECT_FALSE(tb.intr.read()) << "no INT while the sequence is incomplete";
        tb.out(true, 0x20);
        tb.out(true, 0x01);
        EXPECT_EQ(tb.pic.init_state(), Pic8259::InitState::ready);
        tb.out(false, 0x20); // end IR6 from before
        EXPECT_TRUE(tb.intr.read()) << "IR3 was never unmasked by software, yet ICW1 cleared IMR";
        EXPECT_EQ(tb.inta_pair(), 0x23);
    });
}

TEST(Pic8259, Icw1DoesNotTouchRotateInAutoEoiFlag) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x03);
        tb.out(false, 0x80);
        tb.init(0x13, 0x20, 0x03);
        EXPECT_TRUE(tb.pic.rotate_in_auto_eoi());
        EXPECT_TRUE(tb.pic.auto_eoi());
        tb.init(0x13, 0x20, 0x01);
        EXPECT_FALSE(tb.pic.auto_eoi()) << "ICW4 rewrites AEOI";
    });
}

TEST(Pic8259, NoIntBeforeInitialisation) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.set_ir(0, true);
        EXPECT_EQ(tb.pic.init_state(), Pic8259::InitState::power_on);
        EXPECT_FALSE(tb.intr.read());
    });
}
