// System tests of the firmware's promises under hostile or unlucky hosts, with the real ROM on the
// assembled boards (controller_on_lines.h): a give-up drops one response and says so; T1 runs from the
// moment our last character has left the line; an EOT'd frame reaches the main CPU whatever the
// line does next; a flooded port cannot hold the others off.
#include "scenarios/board/interrupt_probe.h"
#include "tests/system/controller_on_lines.h"
#include "tests/support/sc_test.h"

#include <algorithm>
#include <ostream>

using namespace rcsim;
using namespace rcsim::systest;
using proto::Frame;

namespace {

const std::string kEnq = "\x05";

ProtocolHostConfig saturating(std::uint64_t seed) {
    ProtocolHostConfig c;
    c.traffic.pattern = HostTraffic::Pattern::saturate;
    c.traffic.wait_response = false; // the next command right after each EOT
    c.traffic.start = ms(50);
    c.traffic.data_size = 64;
    c.traffic.random_size = true;
    c.traffic.tokens = {{"EC", 3.0}, {"ST", 1.0}};
    c.traffic.seed = seed;
    return c;
}

/// How many times `needle` occurs in `hay`.
std::size_t count_of(const std::string& hay, const std::string& needle) {
    std::size_t n = 0;
    for (std::size_t at = hay.find(needle); at != std::string::npos; at = hay.find(needle, at + 1)) ++n;
    return n;
}

} // namespace

// 1. Hosts that send their next command right after each EOT never leave the controller a gap for
// its responses (the external system wins every collision), so the firmware gives up on them. Each
// give-up drops that one response and tells the main CPU (0x4p/0x5p), one by one: every response
// the main CPU handed over is either at the host or counted as dropped, and nothing is aborted.
TEST(SystemHardening, SaturatingHostsWithoutWaitingGetEachResponseOrItsDropCounted) {
    Board b;
    HostOn h0("host0", b, 0, saturating(1)), h1("host1", b, 1, saturating(2)), h2("host2", b, 2, saturating(3));
    HostOn* hosts[] = {&h0, &h1, &h2};
    Board::run_to(ms(20'000));
    for (HostOn* h : hosts) h->host.stop_traffic();
    // Drain: the hosts go idle, so every response still queued is delivered or given up.
    auto settled = [&] {
        for (unsigned p = 0; p < Board::kPorts; ++p) {
            const MainCpuPortStats& s = b.ctl.main.port_stats(p);
            if (!hosts[p]->host.idle() || s.frames_sent != hosts[p]->host.counters().responses_received + s.responses_dropped)
                return false;
        }
        return true;
    };
    EXPECT_TRUE(Board::run_until(settled, ms(10'000), ms(10)));
    for (unsigned p = 0; p < Board::kPorts; ++p) {
        SCOPED_TRACE("port " + std::to_string(p));
        const MainCpuPortStats& s = b.ctl.main.port_stats(p);
        const ProtocolHost::Counters& c = hosts[p]->host.counters();
        EXPECT_GT(s.frames_sent, 20u) << "the main CPU answered the commands it got";
        EXPECT_EQ(s.frames_sent, c.responses_received + s.responses_dropped) << hosts[p]->log.str().substr(0, 4000);
        EXPECT_EQ(s.tx_aborted, 0u) << "a give-up drops no other frame";
        EXPECT_EQ(s.resets_received, 0u) << "a give-up is not a port reset";
        EXPECT_EQ(s.ack_timeouts, 0u);
        EXPECT_EQ(c.frames_delivered, s.frames_received) << "every command the host saw EOT for arrived";
        EXPECT_EQ(b.ctl.comm.uart[p].stats().overruns, 0u);
    }
}

// 2. T1 for the host's ACK and EOT runs from the moment the controller's ENQ / ETX has left the
// line (82510 transmitter idle) to the START bit of the answer (docs/serial.md "Protocol timers").
// A host that answers each 49 ms after the end of the controller's character (ProtocolHost
// reply_delay: from the end of the stop bit it received to the START of its answer) is within T1:
// the response goes out once, no retry, no duplicate.
TEST(SystemHardening, HostAnsweringLateWithinT1GetsNoDuplicate) {
    Board b;
    ProtocolHostConfig cfg;
    cfg.timing.reply_delay = ms(49);
    HostOn h("host1", b, 1, cfg);
    Board::run_to(k_boot());
    const std::string data = "LATE BUT WITHIN T1, 0123456789";
    b.ctl.main.send(1, "MS", data);
    Board::run_to(ms(600));
    const std::string enc = frame("MS", data);
    EXPECT_EQ(proto::escape(b.from_controller(1)), proto::escape(kEnq + enc)) << b.transcript(1) << h.log.str();
    ASSERT_EQ(h.host.responses().size(), 1u) << h.log.str();
    EXPECT_EQ(h.host.responses()[0], (Frame{"MS", 0, data}));
    EXPECT_EQ(b.ctl.main.port_stats(1).responses_dropped, 0u);
}

// 2b. Control for 2: T1 is still enforced. Answers 55 ms after the end of the character (more
// than T1 + the firmware's tolerance: one character and its 1 ms tick, docs/firmware.md) are
// timeouts: the controller tries again.
TEST(SystemHardening, HostAnsweringAfterT1IsRetried) {
    Board b;
    ProtocolHostConfig cfg;
    cfg.timing.reply_delay = ms(55);
    HostOn h("host1", b, 1, cfg);
    Board::run_to(k_boot());
    b.ctl.main.send(1, "MS", "TOO LATE");
    Board::run_to(ms(400));
    EXPECT_GE(count_of(b.from_controller(1), kEnq), 2u) << b.transcript(1);
}

// 3. A frame the controller has answered with EOT is handed to the main CPU whatever the line does
// next: a BREAK that begins `break_after` after the EOT's START edge, while the frame is still
// being copied into DP-RAM (about 60 us a byte), resets the port only after the hand-over.
struct BreakAfterEot {
    std::size_t data_bytes; // 15: a 24-byte frame; 300: 309 bytes (one chunk either way)
    double break_after_ms;
};
void PrintTo(const BreakAfterEot& b, std::ostream* os) {
    *os << b.data_bytes + 9 << "-byte frame, BREAK " << b.break_after_ms << " ms after the EOT";
}
class SystemBreakAfterEot : public ::testing::TestWithParam<BreakAfterEot> {};

TEST_P(SystemBreakAfterEot, FrameStillReachesTheMainCpu) {
    const BreakAfterEot prm = GetParam();
    Board b;
    const std::string data = pattern(prm.data_bytes);
    sc_time eot_start = sc_core::SC_ZERO_TIME;
    b.on_char = [&](unsigned p, const Board::Char& c) {
        if (p == 0 && c.from == SerialLine::a && c.byte == proto::EOT && eot_start == sc_core::SC_ZERO_TIME)
            eot_start = c.at;
    };
    RawHostConfig cfg;
    cfg.sends.push_back(RawHostConfig::Send{ms(30), kEnq});
    cfg.sends.push_back(RawHostConfig::Send{ms(34), frame("EC", data)});
    RawHost host("host0", cfg);
    host.connect(b.line(0), SerialLine::b);
    ASSERT_TRUE(Board::run_until([&] { return eot_start != sc_core::SC_ZERO_TIME; }, ms(800), us(20)))
        << b.transcript(0);
    Board::run_to(eot_start + us(static_cast<std::uint64_t>(prm.break_after_ms * 1000.0)));
    ASSERT_TRUE(b.ctl.main.received().empty()) << "the BREAK must come before the hand-over is complete";
    b.line(0).insert_break(SerialLine::b, ms(5));
    Board::run_to(sc_core::sc_time_stamp() + ms(100));
    EXPECT_EQ(b.ctl.comm.uart[0].stats().break_detects, 1u);
    ASSERT_EQ(b.ctl.main.received().size(), 1u) << "the EOT'd frame is lost\n" << b.transcript(0);
    EXPECT_EQ(b.ctl.main.received()[0].data, data);
    EXPECT_TRUE(b.ctl.main.malformed().empty());
    EXPECT_EQ(b.ctl.main.port_stats(0).resets_received, 1u) << "the BREAK still reset the port (0x30), after";
    EXPECT_EQ(b.pflag(0), 0);
}

// The EOT starts at once when written; the 24-byte frame's copy ends ~1.5 ms later. A BREAK is
// detected one character (1.146 ms) after it begins, so it lands inside that copy when it begins
// at most ~0.4 ms after the EOT's START. The 309-byte copy takes ~19 ms: points across it.
INSTANTIATE_TEST_SUITE_P(Points, SystemBreakAfterEot,
                         ::testing::Values(BreakAfterEot{15, 0.0}, BreakAfterEot{15, 0.1}, BreakAfterEot{15, 0.2},
                                           BreakAfterEot{300, 0.0}, BreakAfterEot{300, 4.0},
                                           BreakAfterEot{300, 8.0}, BreakAfterEot{300, 10.0}),
                         [](const ::testing::TestParamInfo<BreakAfterEot>& i) {
                             return std::to_string(i.param.data_bytes + 9) + "Bytes" +
                                    std::to_string(static_cast<int>(i.param.break_after_ms * 10)) + "Tenths";
                         });

// 4. A raw host floods port 0 at 115200 bps 8N1 while protocol hosts work ports 1 and 2. Its 82510
// is set to 115200 bps as well (the ROM's port_div[0] = 18.432 MHz / (32 x 115200) = 5,
// docs/firmware.md "Patching the line set-up"; the format stays 8E1, so every character arrives
// as garbage), one character per 87 us: faster than the firmware can take characters in, which a
// 9600-bps line is not. No RS-232 handler keeps interrupts off longer than the bound of
// docs/firmware.md "Interrupts", ports 1 and 2 never overrun, and their commands and responses go
// through (the main loop keeps running).
TEST(SystemHardening, FloodOnPort0At115200CannotStarveTheOtherPorts) {
    Board b;
    b.ctl.comm.rom().at(comm_fw::rom_offset_of(comm_fw::data::port_div)) = 5;
    InterruptProbe probe("probe", b.ctl.comm.cpu,
                         {&b.ctl.comm.uart_int[0], &b.ctl.comm.uart_int[1], &b.ctl.comm.uart_int[2], &b.ctl.int_l},
                         0xC0, 0xD0000, 1020);
    RawHostConfig flood;
    flood.format = SerialFormat::parse("115200,8N1");
    std::string junk;
    for (unsigned i = 0; i < 11'520; ++i) junk.push_back(static_cast<char>(0x20 + (i * 37) % 95)); // 1 s
    flood.sends.push_back(RawHostConfig::Send{ms(30), junk});
    RawHost raw("flood0", flood);
    raw.connect(b.line(0), SerialLine::b);
    ProtocolHostConfig cfg;
    cfg.traffic.pattern = HostTraffic::Pattern::saturate;
    cfg.traffic.start = ms(40);
    cfg.traffic.data_size = 64;
    cfg.traffic.random_size = true;
    HostOn h1("host1", b, 1, cfg), h2("host2", b, 2, cfg);
    Board::run_to(ms(1'100));
    EXPECT_GT(b.ctl.comm.uart[0].stats().overruns, 0u) << "port 0 is flooded (the test's premise)";
    // Interrupts off: an RS-232 handler runs with IF = 0 from INTA to IRET.
    double worst = 0;
    for (unsigned level = 0; level < 3; ++level)
        for (const InterruptRecord* r : probe.of_level(level))
            worst = std::max(worst, to_us(r->iret_done - r->inta1));
    EXPECT_LE(worst, 1300.0) << "the bound of docs/firmware.md \"Interrupts\"";
    for (unsigned p = 1; p < 3; ++p) {
        SCOPED_TRACE("port " + std::to_string(p));
        EXPECT_EQ(b.ctl.comm.uart[p].stats().overruns, 0u);
        // With wait_response the host starts a command only after the previous one's response: all
        // but the one in flight went through, with no failure and no response timeout.
        const auto& c = (p == 1 ? h1 : h2).host.counters();
        EXPECT_GE(c.frames_sent, 2u);
        EXPECT_GE(c.responses_received + 1, c.frames_sent) << (p == 1 ? h1 : h2).log.str();
        EXPECT_EQ(c.frames_failed, 0u);
        EXPECT_EQ(c.response_timeouts, 0u);
    }
}
