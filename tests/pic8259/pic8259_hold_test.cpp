// 8259A: what holds a request (hold(), for the interrupt probe's latency causes) and the
// on_update hook, through PicWithCpu's scripted CPU.
#include "tests/pic8259/pic_with_cpu.h"
#include "tests/support/sc_test.h"

#include <vector>

using rcsim::Pic8259;
using rcsim::test::PicWithCpu;

namespace {

void run(PicWithCpu& tb, std::function<void()> body) {
    tb.body = std::move(body);
    sc_core::sc_start();
}

} // namespace

// Each reason in turn for IR3 with the power-on priority order (IR0 highest): not initialised,
// masked, a higher level in service, a higher request presented first, its own level in service,
// presented. A lower level in service does not hold it.
TEST(Pic8259Hold, EveryReasonInTurn) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        using Kind = Pic8259::Hold::Kind;
        EXPECT_EQ(tb.pic.hold(3).kind, Kind::not_ready);
        tb.init(0x13, 0x20, 0x01, 0x08); // IR3 masked
        EXPECT_EQ(tb.pic.hold(3).kind, Kind::masked);
        tb.out(true, 0x00);
        EXPECT_EQ(tb.pic.hold(3).kind, Kind::none);
        tb.set_ir(5, true);
        tb.inta_pair(); // IR5 in service: lower than IR3, does not hold it
        EXPECT_EQ(tb.pic.hold(3).kind, Kind::none);
        tb.set_ir(1, true);
        EXPECT_EQ(tb.pic.hold(3), (Pic8259::Hold{Kind::priority, 1}));
        tb.inta_pair(); // IR1 in service
        EXPECT_EQ(tb.pic.hold(3), (Pic8259::Hold{Kind::in_service, 1}));
        tb.out(false, 0x61); // specific EOI 1
        EXPECT_EQ(tb.pic.hold(3).kind, Kind::none);
        tb.set_ir(3, true);
        tb.inta_pair(); // IR3 in service: its next request waits for its own EOI
        EXPECT_EQ(tb.pic.hold(3), (Pic8259::Hold{Kind::in_service, 3}));
        tb.out(false, 0x20); // non-specific EOI: the highest in service, IR3
        EXPECT_EQ(tb.pic.hold(3).kind, Kind::none);
    });
}

// With rotated priorities (IR4 lowest after a rotate-on-EOI) IR5 is the highest: IR5 in service
// holds IR3, and IR3 in service does not hold IR6.
TEST(Pic8259Hold, FollowsTheRotation) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        using Kind = Pic8259::Hold::Kind;
        tb.init();
        tb.out(false, 0xC4); // set priority: IR4 lowest
        ASSERT_EQ(tb.pic.lowest_priority(), 4u);
        tb.set_ir(5, true);
        tb.inta_pair();
        EXPECT_EQ(tb.pic.hold(3), (Pic8259::Hold{Kind::in_service, 5}));
        EXPECT_EQ(tb.pic.hold(6), (Pic8259::Hold{Kind::in_service, 5}));
        tb.out(false, 0x20);
        tb.set_ir(3, true);
        tb.inta_pair();
        EXPECT_EQ(tb.pic.hold(6).kind, Kind::none);
        EXPECT_EQ(tb.pic.hold(4), (Pic8259::Hold{Kind::in_service, 3}));
    });
}

// Special mask mode: a masked level in service does not hold the others (as resolve()).
TEST(Pic8259Hold, SpecialMaskModeLetsLowerLevelsThrough) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        using Kind = Pic8259::Hold::Kind;
        tb.init();
        tb.set_ir(1, true);
        tb.inta_pair();
        EXPECT_EQ(tb.pic.hold(3), (Pic8259::Hold{Kind::in_service, 1}));
        tb.out(true, 0x02);  // mask IR1
        tb.out(false, 0x68); // OCW3: set special mask mode
        EXPECT_EQ(tb.pic.hold(3).kind, Kind::none);
        EXPECT_EQ(tb.pic.hold(1).kind, Kind::masked);
    });
}

// on_update follows every settled change: a rise, the INTA cycles, an EOI, a mask write; hold()
// already answers with the new state when it is called.
TEST(Pic8259Hold, OnUpdateAfterEveryChange) {
    PicWithCpu tb("tb");
    std::vector<Pic8259::Hold> seen;
    tb.pic.on_update = [&] { seen.push_back(tb.pic.hold(3)); };
    run(tb, [&] {
        using Kind = Pic8259::Hold::Kind;
        tb.init();
        seen.clear();
        tb.set_ir(0, true);
        ASSERT_FALSE(seen.empty());
        EXPECT_EQ(seen.back(), (Pic8259::Hold{Kind::priority, 0}));
        tb.inta_cycle();
        EXPECT_EQ(seen.back(), (Pic8259::Hold{Kind::in_service, 0}));
        tb.inta_cycle();
        tb.out(false, 0x20);
        EXPECT_EQ(seen.back().kind, Kind::none);
        const std::size_t n = seen.size();
        tb.out(true, 0x08);
        ASSERT_GT(seen.size(), n);
        EXPECT_EQ(seen.back().kind, Kind::masked);
    });
}
