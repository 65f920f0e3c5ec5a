// 8259A bad input: modes the model refuses (SC_REPORT_ERROR naming the ICW), sequencing
// mistakes (SC_REPORT_WARNING, command ignored), and bus misuse (TLM error response + warning).
#include "tests/pic8259/pic_with_cpu.h"
#include "tests/support/sc_test.h"

#include <string>

using rcsim::BusCycle;
using rcsim::Pic8259;
using rcsim::test::PicWithCpu;
using rcsim::test::ScAllowWarnings;

namespace {

void run(PicWithCpu& tb, std::function<void()> body) {
    tb.body = std::move(body);
    sc_core::sc_start();
}

/// Runs `body` and returns the message of the SystemC error it raised ("" if none).
std::string error_of(PicWithCpu& tb, std::function<void()> body) {
    try {
        run(tb, std::move(body));
    } catch (const sc_core::sc_report& r) {
        return r.get_msg();
    }
    return "";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

} // namespace

TEST(Pic8259BadInput, Icw1WithoutIc4IsRefused) {
    PicWithCpu tb("tb");
    const std::string msg = error_of(tb, [&] { tb.out(false, 0x12); });
    EXPECT_TRUE(contains(msg, "ICW1 0x12")) << msg;
    EXPECT_TRUE(contains(msg, "IC4=0")) << msg;
    EXPECT_EQ(tb.pic.init_state(), Pic8259::InitState::power_on);
}

TEST(Pic8259BadInput, Icw1CascadeModeIsRefused) {
    PicWithCpu tb("tb");
    const std::string msg = error_of(tb, [&] { tb.out(false, 0x11); });
    EXPECT_TRUE(contains(msg, "ICW1 0x11")) << msg;
    EXPECT_TRUE(contains(msg, "SNGL=0")) << msg;
}

TEST(Pic8259BadInput, Icw4Mcs80ModeIsRefused) {
    PicWithCpu tb("tb");
    const std::string msg = error_of(tb, [&] {
        tb.out(false, 0x13);
        tb.out(true, 0x20);
        tb.out(true, 0x02);
    });
    EXPECT_TRUE(contains(msg, "ICW4 0x02")) << msg;
    EXPECT_EQ(tb.pic.init_state(), Pic8259::InitState::icw4);
}

TEST(Pic8259BadInput, OcwBeforeIcw1IsIgnoredWithWarning) {
    PicWithCpu tb("tb");
    ScAllowWarnings allow;
    run(tb, [&] {
        tb.out(true, 0x5A);
        tb.out(false, 0x20);
        tb.out(false, 0x0B);
    });
    ASSERT_EQ(allow.messages().size(), 3u);
    EXPECT_TRUE(contains(allow.messages()[0], "OCW1 0x5A")) << allow.messages()[0];
    EXPECT_TRUE(contains(allow.messages()[1], "OCW2 0x20")) << allow.messages()[1];
    EXPECT_TRUE(contains(allow.messages()[2], "OCW3 0x0B")) << allow.messages()[2];
    EXPECT_EQ(tb.pic.imr(), 0x00);
    EXPECT_EQ(tb.pic.eoi_commands(), 0u);
}

TEST(Pic8259BadInput, OcwInsideInitialisationSequenceIsIgnored) {
    PicWithCpu tb("tb");
    ScAllowWarnings allow;
    run(tb, [&] {
        tb.out(false, 0x13);
        tb.out(true, 0x20);
        tb.out(false, 0x0B); // OCW3 while ICW4 is expected
        tb.out(true, 0x01);  // the sequence continues where it was
        EXPECT_EQ(tb.pic.init_state(), Pic8259::InitState::ready);
        tb.set_ir(0, true);
        tb.inta_pair();
        EXPECT_EQ(tb.in(false), 0x00) << "the ignored OCW3 did not select ISR";
    });
    ASSERT_EQ(allow.messages().size(), 1u);
    EXPECT_TRUE(contains(allow.messages()[0], "OCW3 0x0B")) << allow.messages()[0];
    EXPECT_TRUE(contains(allow.messages()[0], "ICW4 is expected")) << allow.messages()[0];
}

TEST(Pic8259BadInput, Icw1RestartsAnUnfinishedSequence) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.out(false, 0x13);
        tb.out(false, 0x1B); // a new ICW1 before ICW2: starts over, now level triggered
        tb.out(true, 0x40);
        tb.out(true, 0x01);
        EXPECT_EQ(tb.pic.init_state(), Pic8259::InitState::ready);
        EXPECT_TRUE(tb.pic.level_triggered());
        EXPECT_EQ(tb.pic.vector_base(), 0x40);
    });
}

TEST(Pic8259BadInput, UnmappedOffsetAndWordAccess) {
    PicWithCpu tb("tb");
    ScAllowWarnings allow;
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x01, 0x3C);
        EXPECT_EQ(tb.out_raw(1, 0xFF).status, tlm::TLM_ADDRESS_ERROR_RESPONSE);
        EXPECT_EQ(tb.out_raw(4, 0xFF).status, tlm::TLM_ADDRESS_ERROR_RESPONSE);
        EXPECT_EQ(tb.out_raw(2, 0xFF, 2).status, tlm::TLM_BURST_ERROR_RESPONSE);
        EXPECT_EQ(tb.pic.imr(), 0x3C) << "no stray write reached OCW1";
    });
    ASSERT_EQ(allow.messages().size(), 3u);
    EXPECT_TRUE(contains(allow.messages()[0], "offset 1")) << allow.messages()[0];
    EXPECT_TRUE(contains(allow.messages()[1], "offset 4")) << allow.messages()[1];
    EXPECT_TRUE(contains(allow.messages()[2], "2-byte access")) << allow.messages()[2];
}

TEST(Pic8259BadInput, A0ShiftZeroMapsRegistersAtConsecutiveOffsets) {
    PicWithCpu tb("tb");
    tb.pic.a0_shift = 0;
    run(tb, [&] {
        tb.out_raw(0, 0x13);
        tb.out_raw(1, 0x20);
        tb.out_raw(1, 0x01);
        tb.out_raw(1, 0x81);
        EXPECT_EQ(tb.pic.imr(), 0x81);
    });
}

TEST(Pic8259BadInput, A0ShiftOutOfRangeIsAnError) {
    PicWithCpu tb("tb");
    tb.pic.a0_shift = 16;
    try {
        sc_core::sc_start();
        FAIL() << "expected an error";
    } catch (const sc_core::sc_report& r) {
        EXPECT_TRUE(contains(r.get_msg(), "a0_shift 16")) << r.get_msg();
    }
}

TEST(Pic8259BadInput, WrongCycleOnIntaSocket) {
    PicWithCpu tb("tb");
    ScAllowWarnings allow;
    run(tb, [&] {
        tb.init();
        std::uint8_t data = 0;
        const auto r = rcsim::bus_access(tb.inta_socket, BusCycle::io_read, 0, &data, 1, sc_core::sc_time_stamp());
        EXPECT_EQ(r.status, tlm::TLM_COMMAND_ERROR_RESPONSE);
    });
    ASSERT_EQ(allow.messages().size(), 1u);
    EXPECT_TRUE(contains(allow.messages()[0], "IOR")) << allow.messages()[0];
}

TEST(Pic8259BadInput, IntaBeforeInitialisationFloatsTheBus) {
    PicWithCpu tb("tb");
    ScAllowWarnings allow;
    run(tb, [&] {
        EXPECT_EQ(tb.inta_cycle(), 0xFF);
        EXPECT_EQ(tb.inta_cycle(), 0xFF);
    });
    EXPECT_EQ(allow.messages().size(), 2u);
    EXPECT_TRUE(tb.inta_log.empty());
}

// transport_dbg reads without side effects: a pending poll is not consumed.
TEST(Pic8259BadInput, DebugReadHasNoSideEffects) {
    PicWithCpu tb("tb");
    run(tb, [&] {
        tb.init(0x13, 0x20, 0x01, 0x0F);
        tb.set_ir(5, true);
        tb.out(false, 0x0C);
        tlm::tlm_generic_payload gp;
        std::uint8_t data = 0;
        gp.set_command(tlm::TLM_READ_COMMAND);
        gp.set_address(0);
        gp.set_data_ptr(&data);
        gp.set_data_length(1);
        EXPECT_EQ(tb.io->transport_dbg(gp), 1u);
        EXPECT_EQ(data, 0x20);
        gp.set_address(2);
        EXPECT_EQ(tb.io->transport_dbg(gp), 1u);
        EXPECT_EQ(data, 0x0F);
        gp.set_command(tlm::TLM_WRITE_COMMAND);
        EXPECT_EQ(tb.io->transport_dbg(gp), 0u) << "debug writes are refused";
        EXPECT_TRUE(tb.pic.poll_pending());
        EXPECT_EQ(tb.pic.isr(), 0x00);
        EXPECT_EQ(tb.in(false), 0x85);
    });
}
