// IDT7130 tests: mailbox rules, BUSY arbitration and its wait states, debug access, bad input.
//
// Timing used below (defaults, see dpram/README.md): 55 ns grade, tAPS 5, tBAA 30, tBDA 30,
// tBDD 45, tWH 20 ns; both ports 8 MHz (125 ns), 4-clock cycles, data phase ends at T3 (375 ns).
// A loser starting at S after a winner that started at 0 waits
//   ceil((500 + tBDA + (read ? tBDD : tWH) - (S + 375)) / 125) clocks, or none if that is <= 0.
#include "tests/dpram/dpram_between_cpus.h"
#include "tests/support/sc_test.h"

#include <string>

using rcsim::BusResult;
using rcsim::Idt7130;
using rcsim::ns;
using rcsim::test::DpramBetweenCpus;
using rcsim::test::ScAllowWarnings;
using Pin = DpramBetweenCpus::PinEvent;
using Pins = std::vector<Pin>;

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

} // namespace

// ---------------------------------------------------------------------------------------------
// Mailboxes

TEST(Idt7130Mailbox, RightWrite3FESetsIntLAndLeftReadClearsIt) {
    DpramBetweenCpus tb("tb");
    std::uint8_t got = 0;
    tb.right_body = [&] { EXPECT_EQ(tb.write_at(tb.right, ns(0), 0x3FE, 0x12).wait_states, 0u); };
    tb.left_body = [&] { got = tb.read_at(tb.left, ns(1000), 0x3FE); };
    sc_core::sc_start();
    EXPECT_EQ(got, 0x12) << "the message is ordinary RAM content";
    // The pin moves when the setting / clearing access ends.
    EXPECT_EQ(tb.pins, Pins({{ns(500), "INT_L", true}, {ns(1500), "INT_L", false}}));
    EXPECT_FALSE(tb.ram.int_l_pending());
}

TEST(Idt7130Mailbox, LeftWrite3FFSetsIntRAndRightReadClearsIt) {
    DpramBetweenCpus tb("tb");
    std::uint8_t got = 0;
    tb.left_body = [&] { tb.write_at(tb.left, ns(250), 0x3FF, 0x21); };
    tb.right_body = [&] {
        sc_core::wait(ns(800));
        EXPECT_TRUE(tb.ram.int_r_pending());
        got = tb.read_at(tb.right, ns(2000), 0x3FF);
    };
    sc_core::sc_start();
    EXPECT_EQ(got, 0x21);
    EXPECT_EQ(tb.pins, Pins({{ns(750), "INT_R", true}, {ns(2500), "INT_R", false}}));
}

TEST(Idt7130Mailbox, WritingOwnMailboxDoesNothing) {
    DpramBetweenCpus tb("tb");
    tb.left_body = [&] { tb.write_at(tb.left, ns(0), 0x3FE, 0x33); };
    tb.right_body = [&] { tb.write_at(tb.right, ns(1000), 0x3FF, 0x44); };
    sc_core::sc_start();
    EXPECT_TRUE(tb.pins.empty());
    EXPECT_FALSE(tb.ram.int_l_pending());
    EXPECT_FALSE(tb.ram.int_r_pending());
    EXPECT_EQ(tb.ram.peek(0x3FE), 0x33) << "still stored";
    EXPECT_EQ(tb.ram.peek(0x3FF), 0x44);
}

// Only the mailbox owner's read clears; the other side reading it, or the owner writing it
// (MAME's rule: clear on read only), leaves INT set.
TEST(Idt7130Mailbox, OnlyTheOwnersReadClears) {
    DpramBetweenCpus tb("tb");
    tb.right_body = [&] {
        tb.write_at(tb.right, ns(0), 0x3FE, 0x01);     // INT_L set
        tb.read_at(tb.right, ns(1000), 0x3FE);         // right reading INT_L's mailbox
    };
    tb.left_body = [&] {
        tb.write_at(tb.left, ns(0) + ns(250), 0x3FF, 0x02); // INT_R set
        tb.read_at(tb.left, ns(2000), 0x3FF);          // left reading INT_R's mailbox
        tb.write_at(tb.left, ns(3000), 0x3FE, 0x03);   // left writing its own mailbox
    };
    sc_core::sc_start();
    EXPECT_TRUE(tb.ram.int_l_pending());
    EXPECT_TRUE(tb.ram.int_r_pending());
    EXPECT_EQ(tb.pins, Pins({{ns(500), "INT_L", true}, {ns(750), "INT_R", true}}));
}

TEST(Idt7130Mailbox, OtherAddressesAreNoMailbox) {
    DpramBetweenCpus tb("tb");
    tb.right_body = [&] {
        for (unsigned a : {0x000u, 0x153u, 0x3FCu, 0x3FDu}) tb.write_at(tb.right, sc_core::sc_time_stamp(), a, 0xFF);
    };
    tb.left_body = [&] {
        for (unsigned a : {0x001u, 0x3FDu}) tb.write_at(tb.left, ns(5000) + sc_core::sc_time_stamp(), a, 0xFF);
    };
    sc_core::sc_start();
    EXPECT_TRUE(tb.pins.empty());
}

TEST(Idt7130Mailbox, WordWriteCoveringBothMailboxesSetsOnlyTheOthersInterrupt) {
    DpramBetweenCpus tb("tb");
    tb.right_body = [&] {
        std::uint8_t data[2] = {0x10, 0x20};
        tb.access_at(tb.right, ns(0), true, 0x3FE, data, 2);
    };
    sc_core::sc_start();
    EXPECT_TRUE(tb.ram.int_l_pending());
    EXPECT_FALSE(tb.ram.int_r_pending());
    EXPECT_EQ(tb.ram.peek(0x3FE), 0x10);
    EXPECT_EQ(tb.ram.peek(0x3FF), 0x20);
}

TEST(Idt7130Mailbox, ResetClearsBothInterruptsKeepsMemory) {
    DpramBetweenCpus tb("tb");
    tb.right_body = [&] { tb.write_at(tb.right, ns(0), 0x3FE, 0x55); };
    tb.left_body = [&] {
        tb.write_at(tb.left, ns(0) + ns(200), 0x3FF, 0x66);
        sc_core::wait(ns(1000));
        EXPECT_TRUE(tb.int_l.read());
        EXPECT_TRUE(tb.int_r.read());
        tb.ram.reset();
    };
    sc_core::sc_start();
    EXPECT_FALSE(tb.ram.int_l_pending());
    EXPECT_FALSE(tb.ram.int_r_pending());
    EXPECT_FALSE(tb.int_l.read());
    EXPECT_FALSE(tb.int_r.read());
    EXPECT_EQ(tb.ram.peek(0x3FE), 0x55);
    EXPECT_EQ(tb.ram.peek(0x3FF), 0x66);
}

// A reset while a set is still on its way to the pin cancels it.
TEST(Idt7130Mailbox, ResetCancelsPendingPinChange) {
    DpramBetweenCpus tb("tb");
    tb.right_body = [&] {
        tb.write_at(tb.right, ns(0), 0x3FE, 0x55);
        tb.ram.reset(); // at t=0, before the write's cycle ends at 500 ns
    };
    sc_core::sc_start();
    EXPECT_TRUE(tb.pins.empty());
    EXPECT_FALSE(tb.int_l.read());
}

// ---------------------------------------------------------------------------------------------
// BUSY arbitration

TEST(Idt7130Busy, WriteWriteLaterPortGetsBusyAndItsWriteLandsLast) {
    DpramBetweenCpus tb("tb");
    BusResult l, r;
    tb.left_body = [&] { l = tb.write_at(tb.left, ns(0), 0x100, 0xAA); };
    tb.right_body = [&] { r = tb.write_at(tb.right, ns(100), 0x100, 0x55); };
    sc_core::sc_start();
    EXPECT_EQ(l.wait_states, 0u);
    // 500 + 30 + 20 - (100 + 375) = 75 ns -> 1 clock
    EXPECT_EQ(r.wait_states, 1u);
    EXPECT_EQ(tb.ram.peek(0x100), 0x55) << "the loser's write is not lost: it lands after the winner's";
    EXPECT_EQ(tb.ram.stats(Idt7130::right_port).busy, 1u);
    EXPECT_EQ(tb.ram.stats(Idt7130::right_port).wait_states, 1u);
    EXPECT_EQ(tb.ram.stats(Idt7130::right_port).busy_wait, ns(125));
    EXPECT_EQ(tb.ram.stats(Idt7130::left_port).busy, 0u);
    EXPECT_EQ(tb.ram.collisions(), 1u);
    ASSERT_EQ(tb.busy.size(), 1u);
    EXPECT_EQ(tb.busy[0].port, Idt7130::right_port);
    EXPECT_EQ(tb.busy[0].address, 0x100u);
    EXPECT_TRUE(tb.busy[0].write);
    EXPECT_EQ(tb.busy[0].busy_low, ns(130));  // later start + tBAA
    EXPECT_EQ(tb.busy[0].busy_high, ns(530)); // winner's cycle end + tBDA
}

TEST(Idt7130Busy, ReadReadCollisionAlsoGetsBusy) {
    DpramBetweenCpus tb("tb");
    BusResult l, r;
    std::uint8_t lv = 0, rv = 0;
    tb.ram.set_speed_grade(55);
    tb.left_body = [&] {
        tb.write_at(tb.left, ns(0), 0x080, 0x5A);
        lv = tb.read_at(tb.left, ns(10000), 0x080, &l);
    };
    tb.right_body = [&] { rv = tb.read_at(tb.right, ns(10050), 0x080, &r); };
    sc_core::sc_start();
    EXPECT_EQ(lv, 0x5A);
    EXPECT_EQ(rv, 0x5A);
    EXPECT_EQ(l.wait_states, 0u);
    // 10500 + 30 + 45 - (10050 + 375) = 150 ns -> 2 clocks
    EXPECT_EQ(r.wait_states, 2u);
    EXPECT_EQ(tb.ram.collisions(), 1u);
}

// Same collision, the loser writing: tWH (20) instead of tBDD (45) after BUSY rises -> 1 clock.
TEST(Idt7130Busy, LosingWriteNeedsTwhLosingReadNeedsTbdd) {
    DpramBetweenCpus tb("tb");
    BusResult w, r;
    tb.left_body = [&] {
        tb.read_at(tb.left, ns(0), 0x200);
        tb.read_at(tb.left, ns(10000), 0x201);
    };
    tb.right_body = [&] {
        w = tb.write_at(tb.right, ns(50), 0x200, 0x01);
        tb.read_at(tb.right, ns(10050), 0x201, &r);
    };
    sc_core::sc_start();
    EXPECT_EQ(w.wait_states, 1u); // 550 - 425 = 125 ns -> 1
    EXPECT_EQ(r.wait_states, 2u); // 575 - 425 = 150 ns -> 2
    EXPECT_EQ(tb.ram.stats(Idt7130::right_port).wait_states, 3u);
    EXPECT_EQ(tb.ram.stats(Idt7130::right_port).busy_wait, ns(375));
}

// Winner reads, loser writes: the read sees the old value, the write lands afterwards.
TEST(Idt7130Busy, WinnersReadSeesOldValueLosersReadSeesWinnersWrite) {
    DpramBetweenCpus tb("tb");
    std::uint8_t left_read = 0, right_read = 0;
    tb.left_body = [&] {
        tb.write_at(tb.left, ns(0), 0x010, 0x11);
        left_read = tb.read_at(tb.left, ns(2000), 0x010);
        tb.write_at(tb.left, ns(4000), 0x020, 0x77);
    };
    tb.right_body = [&] {
        tb.write_at(tb.right, ns(2100), 0x010, 0x22);      // loses to the left read
        right_read = tb.read_at(tb.right, ns(4100), 0x020); // loses to the left write
    };
    sc_core::sc_start();
    EXPECT_EQ(left_read, 0x11);
    EXPECT_EQ(tb.ram.peek(0x010), 0x22);
    EXPECT_EQ(right_read, 0x77);
    EXPECT_EQ(tb.ram.collisions(), 2u);
}

// Both ports at the very same instant: exactly one gets BUSY (never both), and memory holds the
// loser's byte because its write completes last.
TEST(Idt7130Busy, HeadOnCollisionGivesBusyToExactlyOnePort) {
    DpramBetweenCpus tb("tb");
    BusResult l, r;
    tb.left_body = [&] { l = tb.write_at(tb.left, ns(1000), 0x155, 0x4C); };
    tb.right_body = [&] { r = tb.write_at(tb.right, ns(1000), 0x155, 0x52); };
    sc_core::sc_start();
    ASSERT_EQ(tb.ram.collisions(), 1u);
    ASSERT_NE(l.wait_states == 0, r.wait_states == 0) << "BUSY_L and BUSY_R are never both low";
    const bool right_lost = r.wait_states != 0;
    // 1500 + 30 + 20 - (1000 + 375) = 175 ns -> 2 clocks
    EXPECT_EQ(right_lost ? r.wait_states : l.wait_states, 2u);
    EXPECT_EQ(tb.ram.peek(0x155), right_lost ? 0x52 : 0x4C);
    EXPECT_EQ(tb.ram.collisions_inside_aps(), 1u) << "simultaneous starts are inside tAPS";
}

// BUSY that is released before the loser's data phase ends costs nothing, but it happened.
TEST(Idt7130Busy, LateOverlapIsBusyWithoutWaitStates) {
    DpramBetweenCpus tb("tb");
    BusResult r;
    tb.left_body = [&] { tb.write_at(tb.left, ns(0), 0x300, 0x9C); };
    std::uint8_t v = 0;
    tb.right_body = [&] { v = tb.read_at(tb.right, ns(400), 0x300, &r); };
    sc_core::sc_start();
    EXPECT_EQ(r.wait_states, 0u); // 575 < 400 + 375
    EXPECT_EQ(v, 0x9C);
    EXPECT_EQ(tb.ram.collisions(), 1u);
    EXPECT_EQ(tb.ram.stats(Idt7130::right_port).busy_wait, sc_core::SC_ZERO_TIME);
}

TEST(Idt7130Busy, NoBusyWithoutAddressMatch) {
    DpramBetweenCpus tb("tb");
    std::vector<unsigned> waits;
    tb.left_body = [&] {
        tb.write_at(tb.left, ns(0), 0x100, 1);
        tb.write_at(tb.left, ns(1000), 0x3FE, 1);
        tb.write_at(tb.left, ns(2000), 0x200, 1);
    };
    tb.right_body = [&] {
        waits.push_back(tb.write_at(tb.right, ns(0), 0x101, 2).wait_states);   // same time, other address
        waits.push_back(tb.write_at(tb.right, ns(1100), 0x3FF, 2).wait_states); // the two mailboxes
        waits.push_back(tb.write_at(tb.right, ns(2500), 0x200, 2).wait_states); // same address, after the window
    };
    sc_core::sc_start();
    EXPECT_EQ(waits, std::vector<unsigned>({0, 0, 0}));
    EXPECT_EQ(tb.ram.collisions(), 0u);
    EXPECT_TRUE(tb.busy.empty());
}

TEST(Idt7130Busy, WordAccessCollidesOnEitherByte) {
    DpramBetweenCpus tb("tb");
    BusResult r;
    tb.left_body = [&] {
        std::uint8_t data[2] = {0xA0, 0xA1};
        tb.access_at(tb.left, ns(0), true, 0x040, data, 2);
    };
    tb.right_body = [&] { r = tb.write_at(tb.right, ns(100), 0x041, 0xB1); };
    sc_core::sc_start();
    EXPECT_EQ(r.wait_states, 1u);
    EXPECT_EQ(tb.ram.peek(0x040), 0xA0);
    EXPECT_EQ(tb.ram.peek(0x041), 0xB1);
}

TEST(Idt7130Busy, SpeedGradeChangesBusyTiming) {
    DpramBetweenCpus tb("tb");
    BusResult slow, fast;
    tb.left_body = [&] {
        tb.read_at(tb.left, ns(0), 0x001);
        sc_core::wait(ns(5000));
        tb.ram.set_speed_grade(100);
        tb.read_at(tb.left, ns(10000), 0x001);
    };
    tb.right_body = [&] {
        tb.read_at(tb.right, ns(100), 0x001, &fast);  // 55 ns: 500 + 30 + 45 - 475 = 100 -> 1
        tb.read_at(tb.right, ns(10100), 0x001, &slow); // 100 ns: 500 + 50 + 60 - 475 = 135 -> 2
    };
    sc_core::sc_start();
    EXPECT_EQ(fast.wait_states, 1u);
    EXPECT_EQ(slow.wait_states, 2u);
    EXPECT_EQ(tb.ram.speed_grade(), 100u);
}

TEST(Idt7130Busy, GradeTimingTable) {
    const auto g25 = Idt7130::grade_timing(25);
    EXPECT_EQ(g25.t_aps, ns(5));
    EXPECT_EQ(g25.t_baa, ns(20));
    EXPECT_EQ(g25.t_bdd, ns(30));
    EXPECT_EQ(g25.t_wh, ns(15));
    const auto g20 = Idt7130::grade_timing(20);
    EXPECT_EQ(g20.t_bda, g25.t_bda);
    EXPECT_EQ(Idt7130::grade_timing(35).t_bdd, ns(35));
    EXPECT_EQ(Idt7130::grade_timing(55).t_bda, ns(30));
    EXPECT_EQ(Idt7130::grade_timing(100).t_baa, ns(50));
}

// Wait states are counted in the losing port's own clock and cycle length.
TEST(Idt7130Busy, WaitStatesInTheLosersClock) {
    DpramBetweenCpus tb("tb");
    tb.ram.ports[Idt7130::right_port] = {ns(100), 3}; // a 10 MHz, 3-clock main CPU bus
    BusResult r;
    tb.left_body = [&] { tb.write_at(tb.left, ns(0), 0x123, 0x01); };
    tb.right_body = [&] { tb.read_at(tb.right, ns(100), 0x123, &r); };
    sc_core::sc_start();
    // 500 + 30 + 45 - (100 + 2 * 100) = 275 ns -> 3 clocks of 100 ns
    EXPECT_EQ(r.wait_states, 3u);
    EXPECT_EQ(tb.ram.stats(Idt7130::right_port).busy_wait, ns(300));
}

// The loser's stretched cycle holds the location: the winner's next access can lose in turn.
TEST(Idt7130Busy, StretchedLoserCycleBlocksTheNextAccess) {
    DpramBetweenCpus tb("tb");
    tb.ram.ports[Idt7130::right_port] = {ns(125), 8}; // a slow 8-clock right cycle
    BusResult r, l2;
    tb.left_body = [&] {
        tb.write_at(tb.left, ns(0), 0x0AA, 1);
        l2 = tb.write_at(tb.left, ns(500), 0x0AA, 2);
    };
    tb.right_body = [&] { r = tb.write_at(tb.right, ns(100), 0x0AA, 3); };
    sc_core::sc_start();
    EXPECT_EQ(r.wait_states, 0u); // data phase ends 100 + 875 = 975 > 550
    EXPECT_EQ(tb.ram.stats(Idt7130::left_port).busy, 1u) << "left's second write overlaps right's cycle";
    EXPECT_EQ(tb.ram.stats(Idt7130::right_port).busy, 1u);
    // left: 1100 + 30 + 20 - (500 + 375) = 275 -> 3 clocks
    EXPECT_EQ(l2.wait_states, 3u);
    EXPECT_EQ(tb.ram.stats(Idt7130::left_port).wait_states, 3u);
    EXPECT_EQ(tb.ram.peek(0x0AA), 2);
}

// The loser's wait states lengthen its window: [100, 725) instead of [100, 600).
TEST(Idt7130Busy, LosersWaitStatesExtendItsWindow) {
    DpramBetweenCpus tb("tb");
    BusResult r, l2;
    tb.left_body = [&] {
        tb.write_at(tb.left, ns(0), 0x0C0, 1);
        tb.read_at(tb.left, ns(600), 0x0C0, &l2); // after the nominal window, inside the stretched one
        tb.read_at(tb.left, ns(2000), 0x0C0);     // after both
    };
    tb.right_body = [&] { tb.read_at(tb.right, ns(100), 0x0C0, &r); };
    sc_core::sc_start();
    EXPECT_EQ(r.wait_states, 1u); // 575 - 475 = 100 -> 1
    EXPECT_EQ(tb.ram.stats(Idt7130::left_port).busy, 1u);
    EXPECT_EQ(l2.wait_states, 0u); // 725 + 30 + 45 = 800 < 600 + 375
    ASSERT_EQ(tb.busy.size(), 2u);
    EXPECT_EQ(tb.busy[1].busy_high, ns(755));
}

TEST(Idt7130Busy, StartsCloserThanTapsAreCounted) {
    DpramBetweenCpus tb("tb");
    tb.left_body = [&] {
        tb.read_at(tb.left, ns(0), 0x010);
        tb.read_at(tb.left, ns(5000), 0x010);
    };
    tb.right_body = [&] {
        tb.read_at(tb.right, ns(4), 0x010);    // 4 ns < tAPS
        tb.read_at(tb.right, ns(5005), 0x010); // 5 ns = tAPS: the order is guaranteed
    };
    sc_core::sc_start();
    EXPECT_EQ(tb.ram.collisions(), 2u);
    EXPECT_EQ(tb.ram.collisions_inside_aps(), 1u);
}

TEST(Idt7130Busy, MailboxCollisionDelaysTheClearingRead) {
    DpramBetweenCpus tb("tb");
    std::uint8_t v = 0;
    BusResult l;
    tb.right_body = [&] { tb.write_at(tb.right, ns(0), 0x3FE, 0x13); };
    tb.left_body = [&] { v = tb.read_at(tb.left, ns(100), 0x3FE, &l); };
    sc_core::sc_start();
    EXPECT_EQ(v, 0x13);
    EXPECT_EQ(l.wait_states, 1u); // 575 - 475 = 100 -> 1
    // Set when the right write ends (500), cleared when the stretched left read ends (100 + 5 * 125).
    EXPECT_EQ(tb.pins, Pins({{ns(500), "INT_L", true}, {ns(725), "INT_L", false}}));
}

// ---------------------------------------------------------------------------------------------
// Debug access and bad input

TEST(Idt7130Debug, TransportDbgHasNoSideEffects) {
    DpramBetweenCpus tb("tb");
    tb.left_body = [&] {
        tlm::tlm_generic_payload gp;
        std::uint8_t data[4] = {0x01, 0x02, 0x03, 0x04};
        gp.set_command(tlm::TLM_WRITE_COMMAND);
        gp.set_address(0x3FC);
        gp.set_data_ptr(data);
        gp.set_data_length(4);
        EXPECT_EQ(tb.right->transport_dbg(gp), 4u);
        gp.set_command(tlm::TLM_READ_COMMAND);
        gp.set_address(0x3FE);
        EXPECT_EQ(tb.left->transport_dbg(gp), 2u) << "clipped at the end of the array";
        EXPECT_EQ(data[0], 0x03);
        EXPECT_EQ(data[1], 0x04);
        gp.set_address(0x400);
        EXPECT_EQ(tb.left->transport_dbg(gp), 0u);
        // A functional access right after sees no BUSY from the debug accesses.
        EXPECT_EQ(tb.write_at(tb.left, sc_core::sc_time_stamp(), 0x3FE, 0).wait_states, 0u);
    };
    sc_core::sc_start();
    EXPECT_FALSE(tb.ram.int_l_pending());
    EXPECT_FALSE(tb.ram.int_r_pending());
    EXPECT_TRUE(tb.pins.empty());
    EXPECT_EQ(tb.ram.stats(Idt7130::left_port).accesses, 1u);
    EXPECT_EQ(tb.ram.stats(Idt7130::right_port).accesses, 0u);
}

TEST(Idt7130BadInput, AccessOutsideTheArrayIsAnAddressError) {
    DpramBetweenCpus tb("tb");
    ScAllowWarnings allow;
    BusResult a, b;
    tb.left_body = [&] {
        a = tb.write_at(tb.left, ns(0), 0x400, 0xEE);
        std::uint8_t data[2] = {1, 2};
        b = tb.access_at(tb.right, ns(1000), true, 0x3FF, data, 2);
    };
    sc_core::sc_start();
    EXPECT_EQ(a.status, tlm::TLM_ADDRESS_ERROR_RESPONSE);
    EXPECT_EQ(b.status, tlm::TLM_ADDRESS_ERROR_RESPONSE);
    EXPECT_EQ(tb.ram.peek(0x3FF), 0x00) << "the partial word wrote nothing";
    EXPECT_FALSE(tb.ram.int_r_pending());
    ASSERT_EQ(allow.messages().size(), 2u);
    EXPECT_TRUE(contains(allow.messages()[0], "left port")) << allow.messages()[0];
    EXPECT_TRUE(contains(allow.messages()[0], "0x400")) << allow.messages()[0];
    EXPECT_TRUE(contains(allow.messages()[1], "right port")) << allow.messages()[1];
    EXPECT_TRUE(contains(allow.messages()[1], "0x3FF")) << allow.messages()[1];
}

TEST(Idt7130BadInput, OversizedAccessAndByteEnablesAreRefused) {
    DpramBetweenCpus tb("tb");
    ScAllowWarnings allow;
    tb.left_body = [&] {
        std::uint8_t data[4] = {};
        EXPECT_EQ(tb.access_at(tb.left, ns(0), true, 0x000, data, 4).status, tlm::TLM_BURST_ERROR_RESPONSE);
        tlm::tlm_generic_payload gp;
        std::uint8_t be = 0xFF;
        gp.set_command(tlm::TLM_WRITE_COMMAND);
        gp.set_address(0);
        gp.set_data_ptr(data);
        gp.set_data_length(1);
        gp.set_streaming_width(1);
        gp.set_byte_enable_ptr(&be);
        gp.set_byte_enable_length(1);
        sc_core::sc_time d;
        tb.left->b_transport(gp, d);
        EXPECT_EQ(gp.get_response_status(), tlm::TLM_BYTE_ENABLE_ERROR_RESPONSE);
        gp.set_byte_enable_ptr(nullptr);
        gp.set_command(tlm::TLM_IGNORE_COMMAND);
        tb.left->b_transport(gp, d);
        EXPECT_EQ(gp.get_response_status(), tlm::TLM_COMMAND_ERROR_RESPONSE);
    };
    sc_core::sc_start();
    ASSERT_EQ(allow.messages().size(), 3u);
    EXPECT_TRUE(contains(allow.messages()[0], "4-byte access")) << allow.messages()[0];
    EXPECT_EQ(tb.ram.stats(Idt7130::left_port).accesses, 0u);
}

TEST(Idt7130BadInput, UnknownSpeedGradeIsAnError) {
    try {
        Idt7130::grade_timing(70);
        FAIL() << "expected an error";
    } catch (const sc_core::sc_report& r) {
        EXPECT_TRUE(contains(r.get_msg(), "speed grade 70 ns")) << r.get_msg();
    }
}

TEST(Idt7130BadInput, ZeroPortClockIsAnError) {
    DpramBetweenCpus tb("tb");
    tb.ram.ports[Idt7130::left_port].clock = sc_core::SC_ZERO_TIME;
    try {
        sc_core::sc_start();
        FAIL() << "expected an error";
    } catch (const sc_core::sc_report& r) {
        EXPECT_TRUE(contains(r.get_msg(), "left port timing")) << r.get_msg();
    }
}

// ---------------------------------------------------------------------------------------------
// Stable reads (models/bus.h StableReads): the left port declares every location stable but its
// mailbox; a read made ahead of its T1 then answers and arbitrates as the synced one does.

TEST(Idt7130StableReads, EveryLocationButTheLeftMailboxIsDeclared) {
    DpramBetweenCpus tb("tb");
    for (unsigned a = 0; a < Idt7130::kSize; ++a)
        EXPECT_EQ(tb.ram.read_is_stable(a, 1), a != Idt7130::kMailboxLeft) << "address 0x" << std::hex << a;
    EXPECT_FALSE(tb.ram.read_is_stable(0x3FD, 2)) << "a word read that takes in 0x3FE";
    EXPECT_TRUE(tb.ram.read_is_stable(0x3FC, 2));
    EXPECT_FALSE(tb.ram.read_is_stable(0x3FF, 2)) << "past the end";
}

// Two DpramBetweenCpus in one kernel (nothing couples them): the same cycles, the left read of 0x100
// (T1 at 1000 ns) made at its T1 in one and at 200 ns in the other. A right write of the same
// location at 1100 ns overlaps it: BUSY goes to the right port alike in both.
TEST(Idt7130StableReads, AReadAheadOfItsT1AnswersAndArbitratesAsTheSyncedOne) {
    DpramBetweenCpus synced("synced"), ahead("ahead");
    std::uint8_t got_synced = 0, got_ahead = 0;
    for (DpramBetweenCpus* tb : {&synced, &ahead})
        tb->right_body = [tb] {
            tb->write_at(tb->right, ns(0), 0x100, 0x55);
            tb->write_at(tb->right, ns(1100), 0x100, 0x66);
        };
    synced.left_body = [&] { got_synced = synced.read_at(synced.left, ns(1000), 0x100); };
    ahead.left_body = [&] {
        sc_core::wait(ns(200));
        got_ahead = ahead.read_ahead(ahead.left, ns(1000), 0x100);
    };
    sc_core::sc_start();
    EXPECT_EQ(got_synced, 0x55);
    EXPECT_EQ(got_ahead, got_synced);
    ASSERT_EQ(synced.busy.size(), 1u);
    ASSERT_EQ(ahead.busy.size(), 1u);
    EXPECT_EQ(ahead.busy[0].port, Idt7130::right_port);
    EXPECT_EQ(ahead.busy[0].wait_states, synced.busy[0].wait_states);
    EXPECT_EQ(ahead.busy[0].busy_low, synced.busy[0].busy_low);
    EXPECT_EQ(ahead.ram.stats(Idt7130::left_port).accesses, synced.ram.stats(Idt7130::left_port).accesses);
}

// What the declaration does not cover, so the initiator must check it: a write of the other
// port between the read's kernel time and its T1. Read ahead, the old value; synced, the new.
TEST(Idt7130StableReads, AWriteOfTheOtherPortBeforeT1MakesAReadAheadWrong) {
    DpramBetweenCpus synced("synced"), ahead("ahead");
    std::uint8_t got_synced = 0, got_ahead = 0;
    for (DpramBetweenCpus* tb : {&synced, &ahead}) tb->right_body = [tb] { tb->write_at(tb->right, ns(500), 0x200, 0x77); };
    synced.left_body = [&] { got_synced = synced.read_at(synced.left, ns(1000), 0x200); };
    ahead.left_body = [&] { got_ahead = ahead.read_ahead(ahead.left, ns(1000), 0x200); };
    sc_core::sc_start();
    EXPECT_EQ(got_synced, 0x77);
    EXPECT_EQ(got_ahead, 0x00);
}

// Why the left mailbox is left out: its read clears INT_L's flag at once, so a read ahead of
// T1 shows the change to every observer before T1 (int_l_pending(), the 8259A's view of it).
TEST(Idt7130StableReads, TheLeftMailboxReadIsSeenBeforeItsT1) {
    DpramBetweenCpus tb("tb");
    bool pending_after_read = true;
    tb.right_body = [&] { tb.write_at(tb.right, ns(0), Idt7130::kMailboxLeft, 0x12); };
    tb.left_body = [&] {
        sc_core::wait(ns(1000));
        tb.read_ahead(tb.left, ns(3000), Idt7130::kMailboxLeft);
        pending_after_read = tb.ram.int_l_pending(); // at 1000 ns, 2000 ns before the read's T1
    };
    sc_core::sc_start();
    EXPECT_FALSE(pending_after_read);
}
