// The paper's use of the 8259A: IR0..IR3 (82510 #0..#2 and the DP-RAM) under automatic rotation,
// each handler ending with a rotate-on-non-specific EOI (OCW2 0xA0). The order in which the levels
// are served is asserted exactly, over several rounds.
#include "tests/pic8259/pic_with_cpu.h"
#include "tests/support/sc_test.h"

#include <vector>

using rcsim::Pic8259;
using rcsim::test::PicWithCpu;

namespace {

constexpr std::uint8_t kRotateOnEoi = 0xA0;
constexpr std::uint8_t kPlainEoi = 0x20;

/// A CPU serving interrupts with IF clear inside the handler (no nesting): wait for INT, run the
/// two INTA cycles, read the device at handler entry (its request goes away), run the body,
/// issue `eoi` (none when 0) and IRET. `during(level)` runs in the middle of each handler.
/// Returns the levels in the order they were served; stops early if INT stays low for 1 ms.
std::vector<unsigned> serve(PicWithCpu& tb, unsigned count, std::uint8_t eoi,
                            const std::function<void(unsigned)>& during = {}) {
    std::vector<unsigned> order;
    for (unsigned i = 0; i < count; ++i) {
        if (!tb.intr.read()) sc_core::wait(rcsim::us(1000), tb.intr.posedge_event());
        if (!tb.intr.read()) break;
        sc_core::wait(tb.clock.cycles(2)); // to the next instruction boundary
        const unsigned level = tb.inta_pair() - tb.pic.vector_base();
        order.push_back(level);
        tb.ir[level].write(false);          // the handler reads the device's status
        sc_core::wait(tb.clock.cycles(40));
        if (during) during(level);
        sc_core::wait(tb.clock.cycles(40));
        if (eoi) tb.out(false, eoi);
        sc_core::wait(tb.clock.cycles(32)); // IRET
    }
    return order;
}

void raise(PicWithCpu& tb, std::initializer_list<unsigned> levels) {
    for (unsigned n : levels) tb.ir[n].write(true);
    tb.settle();
}

void run(PicWithCpu& tb, std::function<void()> body) {
    tb.body = std::move(body);
    sc_core::sc_start(); // PicWithCpu's body is a checked thread: a stuck one fails the test
}

using Order = std::vector<unsigned>;

} // namespace

// Rounds of four simultaneous requests, nothing new arriving during a round. A previous IR1
// service left IR1 lowest, so each round runs IR2, IR3, IR0, IR1 (fixed priority would give 0..3).
TEST(Pic8259RoundRobin, AllPendingRoundsWithoutMidRoundRequests) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x01, 0xF0);
        raise(tb, {1});
        EXPECT_EQ(serve(tb, 1, kRotateOnEoi), Order({1}));
        EXPECT_EQ(tb.pic.lowest_priority(), 1u);
        Order all;
        for (int round = 0; round < 3; ++round) {
            raise(tb, {0, 1, 2, 3});
            EXPECT_EQ(tb.pic.irr(), 0x0F);
            const Order got = serve(tb, 4, kRotateOnEoi);
            all.insert(all.end(), got.begin(), got.end());
            EXPECT_FALSE(tb.intr.read());
        }
        EXPECT_EQ(all, Order({2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1}));
        for (unsigned n = 0; n < 4; ++n) EXPECT_EQ(tb.pic.acks(n), n == 1 ? 4u : 3u);
    });
}

// Continuous load: every device requests again while it is being served. Rotation still serves
// all four in turn.
TEST(Pic8259RoundRobin, EachLevelRequestsAgainDuringItsOwnService) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x01, 0xF0);
        raise(tb, {0, 1, 2, 3});
        const Order got = serve(tb, 12, kRotateOnEoi, [&](unsigned level) { tb.ir[level].write(true); });
        EXPECT_EQ(got, Order({0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3}));
        EXPECT_TRUE(tb.intr.read()) << "all four still requesting";
    });
}

// Requests arriving at arbitrary points of a round: IR0 again while IR1 is served, IR2 again
// while IR3 is served, IR1 again while IR0 (second time) is served.
TEST(Pic8259RoundRobin, NewRequestsArrivingMidRound) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x01, 0xF0);
        raise(tb, {0, 1, 2, 3});
        unsigned served = 0;
        const Order got = serve(tb, 8, kRotateOnEoi, [&](unsigned level) {
            ++served;
            const unsigned expected_level[] = {0, 1, 2, 3, 0, 1, 2, 3};
            EXPECT_EQ(level, expected_level[(served - 1) % 8]);
            if (served == 2) tb.ir[0].write(true);
            if (served == 4) tb.ir[2].write(true);
            if (served == 5) tb.ir[1].write(true);
        });
        // After IR3 (lowest 3) IR0 goes first; IR1, new during IR0, then ranks above IR2.
        EXPECT_EQ(got, Order({0, 1, 2, 3, 0, 1, 2}));
        EXPECT_EQ(tb.pic.lowest_priority(), 2u);
    });
}

// The same load without rotation: a plain EOI keeps IR0 highest and it starves the others.
// (This is what the rotation tests above would see if 0xA0 did not rotate.)
TEST(Pic8259RoundRobin, FixedPriorityStarvesUnderSameLoad) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x01, 0xF0);
        raise(tb, {0, 1, 2, 3});
        const Order got = serve(tb, 6, kPlainEoi, [&](unsigned level) { tb.ir[level].write(true); });
        EXPECT_EQ(got, Order({0, 0, 0, 0, 0, 0}));
    });
}

// Rotate-in-AEOI mode gives the same round robin without any EOI command.
TEST(Pic8259RoundRobin, RotateInAutoEoiModeServesRoundRobin) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x03, 0xF0);
        tb.out(false, 0x80);
        raise(tb, {0, 1, 2, 3});
        const Order got = serve(tb, 8, 0, [&](unsigned level) { tb.ir[level].write(true); });
        EXPECT_EQ(got, Order({0, 1, 2, 3, 0, 1, 2, 3}));
        EXPECT_EQ(tb.pic.eoi_commands(), 0u);
    });
}
