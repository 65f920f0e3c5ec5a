// System tests of docs/system.md §4 to §6 with the real firmware ROM on the simulated
// communication board, the IDT7130, the behavioural main CPU and simulated external hosts
// (scenarios/host): every assertion is about what is observable on the RS-232C line (a wire tap
// on each SerialLine), what the hosts counted, and what the main CPU received or sent.
#include "tests/system/controller_on_lines.h"
#include "tests/support/sc_test.h"

using namespace rcsim;
using namespace rcsim::systest;
using proto::Frame;

namespace {

const std::string kAck = "\x06", kNak = "\x15", kEot = "\x04", kEnq = "\x05";

/// A raw host on port p of `b` (sends at fixed times, records what it receives).
struct RawOn {
    RawHost host;
    RawOn(const char* name, Board& b, unsigned p, const RawHostConfig& cfg) : host(name, cfg) {
        host.connect(b.line(p), SerialLine::b);
    }
};

void add_raw(RawHostConfig& c, const sc_core::sc_time& at, const std::string& bytes) {
    c.sends.push_back(RawHostConfig::Send{at, bytes});
}

/// A frame with a wrong (but well-formed: two uppercase hex digits) checksum.
std::string with_bad_checksum(const std::string& good) {
    std::string bad = good;
    const std::size_t c1 = bad.size() - 3;
    bad[c1] = bad[c1] == 'A' ? 'B' : 'A';
    return bad;
}

} // namespace

// 1. A good frame gets EOT and reaches the main CPU intact; its echo comes back.
TEST(SystemProtocol, GoodFrameGetsEotAndReachesTheMainCpuIntact) {
    Board b;
    HostOn h("host0", b, 0);
    Board::run_to(k_boot());
    const Frame cmd{"EC", 0, "HELLO, robot 0123456789 {|}~ !\"#$%&'()*+,-./"};
    h.host.send(cmd);
    ASSERT_TRUE(Board::run_until([&] { return h.host.counters().responses_received >= 1; }, ms(500)))
        << h.log.str();
    const auto& c = h.host.counters();
    EXPECT_EQ(c.frames_delivered, 1u);
    EXPECT_EQ(c.naks, 0u);
    EXPECT_EQ(c.timeouts, 0u);
    EXPECT_EQ(c.retries, 0u);
    // On the wire: ENQ -> ACK, frame -> EOT.
    const std::string enc = proto::encode(cmd);
    EXPECT_EQ(b.from_host(0).substr(0, 1 + enc.size()), kEnq + enc) << b.transcript(0);
    EXPECT_EQ(b.from_controller(0).substr(0, 2), kAck + kEot) << b.transcript(0);
    // The main CPU has exactly this frame.
    ASSERT_EQ(b.ctl.main.received().size(), 1u);
    const FrameRecord& r = b.ctl.main.received()[0];
    EXPECT_EQ(r.port, 0u);
    EXPECT_EQ(r.token, "EC");
    EXPECT_EQ(r.bch, 0);
    EXPECT_EQ(r.data, cmd.data);
    EXPECT_TRUE(b.ctl.main.malformed().empty());
    EXPECT_EQ(b.ctl.main.port_stats(0).chunks_received, 1u);
    // ... and answered it: the echo reached the host.
    ASSERT_EQ(h.host.responses().size(), 1u);
    EXPECT_EQ(h.host.responses()[0], cmd);
    EXPECT_EQ(b.pflag(0), 0) << "area free again";
}

// 2. Bad checksum -> NAK, nothing delivered; the port then takes a good frame.
TEST(SystemProtocol, BadChecksumGetsNakAndNothingIsDelivered) {
    Board b;
    const std::string good = frame("EC", "CHECKSUM TEST");
    RawHostConfig cfg;
    add_raw(cfg, ms(30), kEnq);
    add_raw(cfg, ms(34), with_bad_checksum(good));
    RawOn h("host0", b, 0, cfg);
    Board::run_to(ms(120));
    EXPECT_EQ(proto::escape(b.from_controller(0)), proto::escape(kAck + kNak)) << b.transcript(0);
    EXPECT_TRUE(b.ctl.main.received().empty());
    EXPECT_TRUE(b.ctl.main.malformed().empty()) << "a NAKed frame never reaches the main CPU at all";
    EXPECT_EQ(b.ctl.main.port_stats(0).chunks_received, 0u);
    EXPECT_EQ(b.pflag(0), 0);
}

// 3. A parity error on one frame byte -> NAK, nothing delivered.
TEST(SystemProtocol, ParityErrorOnAFrameByteGetsNak) {
    Board b;
    const std::string good = frame("EC", "PARITY TEST");
    RawHostConfig cfg;
    add_raw(cfg, ms(30), kEnq);
    add_raw(cfg, ms(34), good);
    RawOn h("host0", b, 0, cfg);
    // host character 0 is the ENQ, 1 the SOH; 8 is a data byte
    b.line(0).inject(SerialLine::b, 8, FaultKind::flip_data_bit, 0);
    Board::run_to(ms(120));
    EXPECT_EQ(proto::escape(b.from_controller(0)), proto::escape(kAck + kNak)) << b.transcript(0);
    EXPECT_TRUE(b.ctl.main.received().empty());
    EXPECT_TRUE(b.ctl.main.malformed().empty());
    EXPECT_EQ(b.ctl.main.port_stats(0).chunks_received, 0u);
    EXPECT_EQ(b.ctl.comm.uart[0].stats().parity_errors, 1u);
    EXPECT_EQ(b.pflag(0), 0);
}

// 4. A gap over T2 (20 ms) between two frame bytes: the partial frame is dropped silently (no EOT,
// no NAK, nothing to the main CPU) and the port takes the next good frame.
TEST(SystemProtocol, T2GapDropsThePartialFrameAndThePortTakesTheNextOne) {
    Board b;
    const std::string first = frame("EC", "DROPPED BY T2");
    const std::string second = frame("EC", "AFTER THE GAP");
    RawHostConfig cfg;
    add_raw(cfg, ms(30), kEnq);
    add_raw(cfg, ms(34), first.substr(0, 8));  // last stop bit at ~43.2 ms
    add_raw(cfg, ms(70), first.substr(8));     // ~28 ms later: over T2
    add_raw(cfg, ms(110), kEnq);
    add_raw(cfg, ms(114), second);
    RawOn h("host0", b, 0, cfg);
    Board::run_to(ms(100));
    EXPECT_EQ(proto::escape(b.from_controller(0)), proto::escape(kAck)) << "no EOT, no NAK\n" << b.transcript(0);
    EXPECT_EQ(b.pflag(0), 0) << "the dropped frame's area is free";
    Board::run_to(ms(150));
    unsigned enqs = 0;
    EXPECT_EQ(proto::escape(strip_trailing_enqs(b.from_controller(0), enqs)), proto::escape(kAck + kAck + kEot))
        << b.transcript(0);
    ASSERT_EQ(b.ctl.main.received().size(), 1u);
    EXPECT_EQ(b.ctl.main.received()[0].data, "AFTER THE GAP");
    EXPECT_TRUE(b.ctl.main.malformed().empty());
    EXPECT_EQ(b.ctl.main.port_stats(0).chunks_received, 1u);
    EXPECT_EQ(b.ctl.main.port_stats(0).partial_dropped, 0u) << "no chunk of the partial frame went out";
}

// 4b. Control for 4: the same frame with a gap under T2 is accepted.
TEST(SystemProtocol, GapUnderT2IsAccepted) {
    Board b;
    const std::string f = frame("EC", "DROPPED BY T2");
    RawHostConfig cfg;
    add_raw(cfg, ms(30), kEnq);
    add_raw(cfg, ms(34), f.substr(0, 8));
    add_raw(cfg, ms(57), f.substr(8)); // stop bit to stop bit ~15 ms
    RawOn h("host0", b, 0, cfg);
    Board::run_to(ms(90));
    EXPECT_EQ(proto::escape(b.from_controller(0).substr(0, 2)), proto::escape(kAck + kEot)) << b.transcript(0);
    ASSERT_EQ(b.ctl.main.received().size(), 1u);
    EXPECT_EQ(b.ctl.main.received()[0].data, "DROPPED BY T2");
}

// 5. ENQ while the port's DP-RAM area is in use (pflag[p] != 0) -> NAK; free again -> ACK.
TEST(SystemProtocol, EnqWhileTheAreaIsBusyGetsNak) {
    Board b;
    RawHostConfig cfg;
    add_raw(cfg, ms(31), kEnq);
    add_raw(cfg, ms(45), kEnq);
    RawOn h("host0", b, 0, cfg);
    Board::run_to(ms(30));
    ASSERT_EQ(b.pflag(0), 0) << "the firmware freed every area at start-up";
    b.dpram_poke(1 * 340 + 339, 2); // another port's area: must not matter
    b.dpram_poke(0 * 340 + 339, 2); // RBT_USE: the main CPU holds port 0's area
    Board::run_to(ms(40));
    EXPECT_EQ(proto::escape(b.from_controller(0)), proto::escape(kNak)) << b.transcript(0);
    EXPECT_EQ(b.pflag(0), 2) << "the comm CPU did not take a busy area";
    b.dpram_poke(0 * 340 + 339, 0);
    Board::run_to(ms(50));
    EXPECT_EQ(proto::escape(b.from_controller(0)), proto::escape(kNak + kAck)) << b.transcript(0);
    EXPECT_EQ(b.pflag(0), 1) << "EXT_USE: claimed by the comm CPU for the host's frame";
}

// 5b. The same with a real reason for the busy area: the main CPU is sending a long (9-chunk)
// frame through port 0's area when the host's ENQ comes.
TEST(SystemProtocol, EnqWhileTheMainCpuWritesALongFrameGetsNak) {
    Board b;
    RawHostConfig cfg;
    add_raw(cfg, ms(40), kEnq);
    RawOn h("host0", b, 0, cfg);
    Board::run_to(ms(30));
    b.ctl.main.send(0, "EC", pattern(3000));
    Board::run_to(ms(40));
    ASSERT_EQ(b.pflag(0), 2) << "the main CPU holds the area (RBT_USE) while its chunks go";
    Board::run_to(ms(45));
    EXPECT_EQ(proto::escape(b.from_controller(0)), proto::escape(kNak)) << b.transcript(0);
    EXPECT_EQ(b.pflag(0), 2);
}

// 6. A 3000-byte EC frame crosses DP-RAM in 339-byte chunks intact, and so does its echo.
TEST(SystemProtocol, ThreeThousandByteFrameCrossesDpramInChunksAndComesBackIntact) {
    Board b;
    HostOn h("host0", b, 0);
    Board::run_to(k_boot());
    const Frame cmd{"EC", 0, pattern(3000)};
    h.host.send(cmd);
    // 3009 bytes each way at 1.146 ms a character: ~3.5 s each way.
    ASSERT_TRUE(Board::run_until([&] { return h.host.counters().responses_received >= 1; }, ms(8000), ms(20)))
        << h.log.str();
    const auto& c = h.host.counters();
    EXPECT_EQ(c.frames_delivered, 1u);
    EXPECT_EQ(c.naks, 0u);
    EXPECT_EQ(c.retries, 0u);
    EXPECT_EQ(c.naks_sent, 0u);
    ASSERT_EQ(b.ctl.main.received().size(), 1u);
    EXPECT_EQ(b.ctl.main.received()[0].token, "EC");
    EXPECT_TRUE(b.ctl.main.received()[0].data == cmd.data) << "data differs";
    const auto& ps = b.ctl.main.port_stats(0);
    EXPECT_EQ(ps.bytes_received, 3009u) << "SOH, token, STX, BCH, 3000 data bytes, checksum, ETX";
    EXPECT_EQ(ps.chunks_received, 9u) << "8 full chunks of 339 bytes and the last of 297";
    EXPECT_EQ(ps.chunks_sent, 9u);
    EXPECT_EQ(ps.frames_sent, 1u);
    EXPECT_TRUE(b.ctl.main.malformed().empty());
    ASSERT_EQ(h.host.responses().size(), 1u);
    EXPECT_TRUE(h.host.responses()[0] == cmd) << "echo differs";
    EXPECT_EQ(b.from_controller(0).substr(2), kEnq + proto::encode(cmd)) << "ACK EOT, then ENQ and the echo";
}

// 7. A frame the main CPU starts (MainCpu::send) reaches the host: ENQ, ACK, frame, EOT.
TEST(SystemProtocol, ControllerInitiatedFrameReachesTheHost) {
    Board b;
    HostOn h("host1", b, 1);
    Board::run_to(k_boot());
    b.ctl.main.send(1, "MS", "ALARM,3,AXIS 2 FOLLOWING ERROR", 0x05);
    ASSERT_TRUE(Board::run_until([&] { return h.host.counters().responses_received >= 1; }, ms(300)))
        << h.log.str();
    ASSERT_EQ(h.host.responses().size(), 1u);
    EXPECT_EQ(h.host.responses()[0], (Frame{"MS", 0x05, "ALARM,3,AXIS 2 FOLLOWING ERROR"}));
    const std::string enc = frame("MS", "ALARM,3,AXIS 2 FOLLOWING ERROR", 0x05);
    EXPECT_EQ(proto::escape(b.from_controller(1)), proto::escape(kEnq + enc)) << b.transcript(1);
    Board::run_to(sc_core::sc_time_stamp() + ms(5));
    EXPECT_EQ(proto::escape(b.from_host(1)), proto::escape(kAck + kEot)) << b.transcript(1);
    EXPECT_EQ(h.host.counters().enqs_received, 1u);
    EXPECT_EQ(h.host.counters().naks_sent, 0u);
    EXPECT_EQ(b.ctl.main.port_stats(1).frames_sent, 1u);
    EXPECT_EQ(b.ctl.main.port_stats(1).ack_timeouts, 0u);
    EXPECT_EQ(b.pflag(1), 0);
    EXPECT_TRUE(b.from_controller(0).empty() && b.from_controller(2).empty()) << "other ports silent";
}

// 8. ENQ collision: the controller's ENQ for its own frame and the host's ENQ cross on the line.
// The external system wins: the controller ACKs the host, takes its frame, then retries its own.
TEST(SystemProtocol, EnqCollisionTheExternalSystemWinsAndTheControllerRetries) {
    Board b;
    HostOn h("host0", b, 0);
    const Frame theirs{"EC", 0, "HOST FRAME"};
    bool fired = false;
    b.on_char = [&](unsigned p, const Board::Char& c) {
        if (p == 0 && c.from == SerialLine::a && c.byte == proto::ENQ && !fired) {
            fired = true;
            h.host.send(theirs); // the host's ENQ starts in the same instant
        }
    };
    Board::run_to(k_boot());
    b.ctl.main.send(0, "MS", "MINE");
    ASSERT_TRUE(Board::run_until([&] { return h.host.counters().responses_received >= 2; }, ms(600)))
        << h.log.str() << b.transcript(0);
    ASSERT_TRUE(fired);
    const auto& w = b.wire[0];
    ASSERT_GE(w.size(), 2u);
    EXPECT_EQ(w[0].from, SerialLine::a);
    EXPECT_EQ(w[1].from, SerialLine::b);
    EXPECT_EQ(w[0].at, w[1].at) << "both ENQs start at the same time";
    const auto& c = h.host.counters();
    EXPECT_EQ(c.collisions, 1u);
    EXPECT_EQ(c.frames_delivered, 1u);
    EXPECT_EQ(c.naks, 0u);
    EXPECT_EQ(c.timeouts, 0u);
    EXPECT_EQ(c.retries, 0u);
    EXPECT_EQ(c.enqs_received, 2u) << "the retried MS and the echo of EC";
    ASSERT_EQ(h.host.responses().size(), 2u);
    EXPECT_EQ(h.host.responses()[0], (Frame{"MS", 0, "MINE"})) << "the controller's own frame, retried first";
    EXPECT_EQ(h.host.responses()[1], theirs) << "then the echo";
    ASSERT_EQ(b.ctl.main.received().size(), 1u);
    EXPECT_EQ(b.ctl.main.received()[0].data, "HOST FRAME");
    // Exactly this on the wire, each side:
    EXPECT_EQ(proto::escape(b.from_controller(0)),
              proto::escape(kEnq + kAck + kEot + kEnq + frame("MS", "MINE") + kEnq + frame("EC", "HOST FRAME")))
        << b.transcript(0);
    Board::run_to(sc_core::sc_time_stamp() + ms(5));
    EXPECT_EQ(proto::escape(b.from_host(0)), proto::escape(kEnq + frame("EC", "HOST FRAME") + kAck + kEot + kAck + kEot))
        << b.transcript(0);
}

namespace {
/// Port reset tests: ENQ and the first 6 bytes of a frame, the reset at 42 ms, the rest of that
/// frame at 46 ms (within T2 of its last byte, so without the reset it would complete), then a
/// new ENQ and a good frame.
RawHostConfig reset_script() {
    RawHostConfig cfg;
    const std::string first = frame("EC", "CUT BY A RESET");
    add_raw(cfg, ms(30), kEnq);
    add_raw(cfg, ms(34), first.substr(0, 6)); // last stop bit at ~40.9 ms
    add_raw(cfg, ms(46), first.substr(6));
    add_raw(cfg, ms(90), kEnq);
    add_raw(cfg, ms(94), frame("EC", "AFTER THE RESET"));
    return cfg;
}
void expect_reset_outcome(Board& b) {
    Board::run_to(ms(88));
    EXPECT_EQ(proto::escape(b.from_controller(0)), proto::escape(kAck)) << "the rest of the cut frame is ignored\n"
                                                                        << b.transcript(0);
    Board::run_to(ms(135));
    unsigned enqs = 0;
    EXPECT_EQ(proto::escape(strip_trailing_enqs(b.from_controller(0), enqs)), proto::escape(kAck + kAck + kEot))
        << b.transcript(0);
    ASSERT_EQ(b.ctl.main.received().size(), 1u);
    EXPECT_EQ(b.ctl.main.received()[0].data, "AFTER THE RESET");
    EXPECT_TRUE(b.ctl.main.malformed().empty());
}
} // namespace

// 9-. Control for 9: the reset script without a reset completes the first frame.
TEST(SystemProtocol, WithoutAResetTheInterruptedFrameCompletes) {
    Board b;
    RawOn h("host0", b, 0, reset_script());
    Board::run_to(ms(88));
    EXPECT_EQ(proto::escape(b.from_controller(0).substr(0, 2)), proto::escape(kAck + kEot)) << b.transcript(0);
    ASSERT_GE(b.ctl.main.received().size(), 1u);
    EXPECT_EQ(b.ctl.main.received()[0].data, "CUT BY A RESET");
}

// 9a. Port reset by the mailbox word 0x3p from the main CPU.
TEST(SystemProtocol, PortResetByMailboxWord) {
    Board b;
    RawOn h("host0", b, 0, reset_script());
    Board::run_to(ms(42));
    ASSERT_EQ(b.pflag(0), 1) << "the host's frame holds the area";
    b.ctl.main.request_port_reset(0);
    Board::run_to(ms(45));
    EXPECT_EQ(b.pflag(0), 0) << "the reset freed the area";
    EXPECT_EQ(b.ctl.main.port_stats(0).resets_sent, 1u);
    EXPECT_EQ(b.ctl.main.port_stats(0).resets_received, 0u) << "a reset the main CPU asked for is not echoed";
    expect_reset_outcome(b);
}

// 9b. Port reset by a BREAK on the line.
TEST(SystemProtocol, PortResetByBreak) {
    Board b;
    RawOn h("host0", b, 0, reset_script());
    Board::run_to(ms(42));
    ASSERT_EQ(b.pflag(0), 1);
    b.line(0).insert_break(SerialLine::b, ms(3));
    // the handler only asks for the reset; the main loop runs it (the 82510 set-up, ~0.9 ms)
    Board::run_to(ms(46));
    EXPECT_EQ(b.ctl.comm.uart[0].stats().break_detects, 1u);
    EXPECT_EQ(b.pflag(0), 0) << "the reset freed the area";
    EXPECT_EQ(b.ctl.main.port_stats(0).resets_received, 1u) << "the comm CPU told the main CPU (0x30)";
    expect_reset_outcome(b);
}

// 3b. The protocol host's own recovery from a NAKed frame on the real firmware: the frame is
// delivered exactly once in the end, intact, and nothing of the bad copy reaches the main CPU.
TEST(SystemProtocol, HostRecoversFromANakedFrameAndTheFrameArrivesOnce) {
    Board b;
    HostOn h("host0", b, 0);
    Board::run_to(k_boot());
    b.line(0).inject(SerialLine::b, 8, FaultKind::flip_data_bit, 3); // a data byte of the first copy
    const Frame cmd{"EC", 0, "RETRIED AFTER NAK"};
    h.host.send(cmd);
    ASSERT_TRUE(Board::run_until([&] { return h.host.counters().responses_received >= 1; }, ms(800)))
        << h.log.str() << b.transcript(0);
    const auto& c = h.host.counters();
    EXPECT_EQ(c.frames_delivered, 1u) << h.log.str();
    EXPECT_EQ(c.frames_failed, 0u);
    EXPECT_GE(c.naks, 1u);
    ASSERT_EQ(b.ctl.main.received().size(), 1u);
    EXPECT_EQ(b.ctl.main.received()[0].data, cmd.data);
    EXPECT_TRUE(b.ctl.main.malformed().empty());
    ASSERT_EQ(h.host.responses().size(), 1u);
    EXPECT_EQ(h.host.responses()[0], cmd);
}

// 3c. docs/system.md §6.2: a sender resends the whole frame after NAK. After its NAK the receiver
// is idle again, so the retry is a new transfer: ENQ, ACK, the whole frame, EOT (docs/serial.md).
TEST(SystemProtocol, FrameRetriedAfterNakStartsWithEnqAndGetsEot) {
    Board b;
    HostOn h("host0", b, 0);
    Board::run_to(k_boot());
    b.line(0).inject(SerialLine::b, 8, FaultKind::flip_data_bit, 3);
    h.host.send(Frame{"EC", 0, "RETRIED AFTER NAK"});
    ASSERT_TRUE(Board::run_until([&] { return h.host.counters().frames_delivered >= 1; }, ms(300))) << h.log.str();
    EXPECT_EQ(h.host.counters().naks, 1u);
    EXPECT_EQ(h.host.counters().retries, 1u) << h.log.str();
    EXPECT_EQ(h.host.counters().timeouts, 0u) << h.log.str();
    // ACK, NAK (the corrupted frame), then ACK to the retry's ENQ and EOT for the whole frame.
    EXPECT_EQ(proto::escape(b.from_controller(0).substr(0, 4)), proto::escape(kAck + kNak + kAck + kEot))
        << b.transcript(0);
}

// 7b. The controller retries its own frame after a NAK to its ENQ, waiting 10 ms x attempt.
TEST(SystemProtocol, ControllerRetriesAfterNakWithBackoff) {
    Board b;
    ProtocolHostConfig cfg;
    cfg.nak_enqs = 2;
    HostOn h("host0", b, 0, cfg);
    Board::run_to(k_boot());
    b.ctl.main.send(0, "MS", "RETRY ME");
    ASSERT_TRUE(Board::run_until([&] { return h.host.counters().responses_received >= 1; }, ms(400)))
        << h.log.str() << b.transcript(0);
    EXPECT_EQ(h.host.responses()[0], (Frame{"MS", 0, "RETRY ME"}));
    EXPECT_EQ(h.host.counters().enqs_received, 3u);
    EXPECT_EQ(h.host.counters().naks_sent, 2u);
    EXPECT_EQ(proto::escape(b.from_controller(0)), proto::escape(kEnq + kEnq + kEnq + frame("MS", "RETRY ME")))
        << b.transcript(0);
    // Retry n starts n x 10 ms after the NAK arrived (1 ms tick resolution, plus the main loop).
    const auto& w = b.wire[0];
    ASSERT_GE(w.size(), 5u);
    ASSERT_EQ(w[1].byte, proto::NAK);
    ASSERT_EQ(w[3].byte, proto::NAK);
    const double wait1 = to_us(w[2].at - (w[1].at + test::char_time_9600_8e1())) / 1000.0;
    const double wait2 = to_us(w[4].at - (w[3].at + test::char_time_9600_8e1())) / 1000.0;
    EXPECT_GE(wait1, 9.0) << b.transcript(0);
    EXPECT_LE(wait1, 12.0) << b.transcript(0);
    EXPECT_GE(wait2, 19.0) << b.transcript(0);
    EXPECT_LE(wait2, 22.0) << b.transcript(0);
    EXPECT_EQ(b.ctl.main.port_stats(0).resets_received, 0u);
}

// 7c. After 3 retries (4 ENQs refused) the controller gives up on that frame and tells the main
// CPU (0x40: given up, it never left whole); the port is not reset, and then serves the host
// normally.
TEST(SystemProtocol, ControllerGivesUpAfterThreeRetriesAndReportsIt) {
    Board b;
    ProtocolHostConfig cfg;
    cfg.nak_enqs = 4;
    HostOn h("host0", b, 0, cfg);
    Board::run_to(k_boot());
    b.ctl.main.send(0, "MS", "NEVER TAKEN");
    ASSERT_TRUE(Board::run_until([&] { return b.ctl.main.port_stats(0).responses_dropped >= 1; }, ms(300)))
        << h.log.str() << b.transcript(0);
    Board::run_to(sc_core::sc_time_stamp() + ms(60));
    EXPECT_EQ(proto::escape(b.from_controller(0)), proto::escape(kEnq + kEnq + kEnq + kEnq)) << b.transcript(0);
    EXPECT_EQ(h.host.counters().enqs_received, 4u);
    EXPECT_TRUE(h.host.responses().empty());
    EXPECT_EQ(b.ctl.main.port_stats(0).responses_dropped, 1u);
    EXPECT_EQ(b.ctl.main.port_stats(0).responses_dropped_sent, 0u) << "no ENQ was ever ACKed";
    EXPECT_EQ(b.ctl.main.port_stats(0).resets_received, 0u) << "a give-up is not a port reset";
    EXPECT_EQ(b.pflag(0), 0);
    // the port works afterwards
    h.host.send(Frame{"EC", 0, "STILL ALIVE"});
    ASSERT_TRUE(Board::run_until([&] { return h.host.counters().responses_received >= 1; }, ms(300)))
        << h.log.str() << b.transcript(0);
    EXPECT_EQ(h.host.counters().frames_delivered, 1u);
    EXPECT_EQ(h.host.responses()[0], (Frame{"EC", 0, "STILL ALIVE"}));
}

// 4c. After our ACK the first frame byte must come within T1 (50 ms): silence drops the transfer
// without an answer and frees the area.
TEST(SystemProtocol, SilenceAfterAckFreesThePortAfterT1) {
    Board b;
    RawHostConfig cfg;
    add_raw(cfg, ms(30), kEnq);
    add_raw(cfg, ms(100), kEnq);
    add_raw(cfg, ms(104), frame("EC", "LATE"));
    RawOn h("host0", b, 0, cfg);
    Board::run_to(ms(60));
    EXPECT_EQ(b.pflag(0), 1) << "still waiting within T1";
    Board::run_to(ms(99));
    EXPECT_EQ(b.pflag(0), 0) << "T1 expired: area freed";
    EXPECT_EQ(proto::escape(b.from_controller(0)), proto::escape(kAck)) << "no NAK for silence\n" << b.transcript(0);
    Board::run_to(ms(130));
    unsigned enqs = 0;
    EXPECT_EQ(proto::escape(strip_trailing_enqs(b.from_controller(0), enqs)), proto::escape(kAck + kAck + kEot))
        << b.transcript(0);
    ASSERT_EQ(b.ctl.main.received().size(), 1u);
    EXPECT_EQ(b.ctl.main.received()[0].data, "LATE");
}
