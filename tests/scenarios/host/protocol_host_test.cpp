// The protocol host against a scripted fake controller, on every path of docs/system.md §5 and §6:
// ACK, NAK then retry, timeout then retry, give-up, bad checksum -> NAK, T2 gap -> drop,
// ENQ collision; and its traffic generators.
#include "scenarios/host/protocol_host.h"

#include "models/clock.h"
#include "tests/support/sc_test.h"
#include "tests/support/serial_times.h"

#include <deque>
#include <map>

using namespace rcsim;
using namespace rcsim::proto;
using sc_core::sc_time;

namespace {

const sc_time k_char = test::char_time_9600_8e1();

/// A scripted controller: answers trigger bytes from per-trigger reply lists (default: ENQ ->
/// ACK, ETX -> EOT, "" = stay silent) after `delay`, and sends scheduled byte strings.
struct FakeController : sc_core::sc_module, SerialEndpoint {
    struct Rx {
        sc_time at;
        std::uint8_t byte;
    };
    SerialFormat fmt = SerialFormat::rs232(9600);
    SerialLine& line;
    std::vector<Rx> got;
    std::map<std::uint8_t, std::deque<std::string>> replies;
    sc_time delay = ms(1);
    std::multimap<sc_time, std::pair<std::string, sc_time>> outbox; // at -> bytes, extra gap
    sc_core::sc_event wake;

    FakeController(sc_core::sc_module_name n, SerialLine& l) : sc_module(n), line(l) {
        line.attach(SerialLine::b, *this);
        test::spawn_forever([this] { sender(); }, "sender"); // serves the outbox until the end
    }
    void send_at(const sc_time& at, const std::string& bytes, const sc_time& gap = sc_core::SC_ZERO_TIME) {
        outbox.emplace(at, std::make_pair(bytes, gap));
        wake.notify(sc_core::SC_ZERO_TIME);
    }
    void sender() {
        for (;;) {
            if (outbox.empty()) {
                wait(wake);
                continue;
            }
            const auto it = outbox.begin();
            const sc_time now = sc_core::sc_time_stamp();
            if (it->first > now) {
                wait(it->first - now, wake);
                continue;
            }
            const auto [bytes, gap] = it->second;
            outbox.erase(it);
            for (unsigned char c : bytes) {
                line.transmit(SerialLine::b, SerialWord::encode(c, fmt));
                wait(fmt.frame_time() + gap);
            }
        }
    }
    SerialFormat rx_format() const override { return fmt; }
    void rx_char(const SerialRx& c) override {
        const auto b = static_cast<std::uint8_t>(c.data);
        got.push_back(Rx{c.stop, b});
        std::string reply;
        auto& q = replies[b];
        if (!q.empty()) {
            reply = q.front();
            q.pop_front();
        } else if (b == ENQ) {
            reply = "\x06";
        } else if (b == ETX) {
            reply = "\x04";
        }
        if (!reply.empty()) send_at(sc_core::sc_time_stamp() + delay, reply);
    }
    void rx_break(bool) override {}
    std::vector<sc_time> times_of(std::uint8_t b) const {
        std::vector<sc_time> t;
        for (const auto& r : got)
            if (r.byte == b) t.push_back(r.at);
        return t;
    }
    std::string bytes() const {
        std::string s;
        for (const auto& r : got) s += static_cast<char>(r.byte);
        return s;
    }
};

struct HostAndFake {
    SerialLine line{"line"};
    ProtocolHost host;
    FakeController fake{"fake", line};
    explicit HostAndFake(ProtocolHostConfig cfg = {}) : host("host", cfg) { host.connect(line, SerialLine::a); }
};

ProtocolHostConfig no_wait() {
    ProtocolHostConfig c;
    c.traffic.wait_response = false;
    return c;
}

const Frame k_cmd{"EC", 0, "hello"};

} // namespace

TEST(ProtocolHost, CommandAckedAndDelivered) {
    HostAndFake b(no_wait());
    b.host.send(k_cmd);
    sc_core::sc_start(ms(200));
    EXPECT_EQ(b.fake.bytes(), "\x05" + encode(k_cmd));
    const auto& c = b.host.counters();
    EXPECT_EQ(c.frames_sent, 1u);
    EXPECT_EQ(c.frames_delivered, 1u);
    EXPECT_EQ(c.naks + c.retries + c.timeouts + c.frames_failed, 0u);
    // ENQ ends at k_char; ACK 1 ms later takes k_char; the frame starts on the ACK's stop bit.
    const sc_time ack_stop = k_char + ms(1) + k_char;
    ASSERT_EQ(b.fake.times_of(SOH).size(), 1u);
    EXPECT_EQ(b.fake.times_of(SOH)[0], ack_stop + k_char);
    EXPECT_EQ(b.fake.times_of(ETX)[0], ack_stop + k_char * 14.0);
    ASSERT_EQ(b.host.delivery_us().count(), 1u);
    const sc_time eot_stop = ack_stop + k_char * 14.0 + ms(1) + k_char;
    EXPECT_DOUBLE_EQ(b.host.delivery_us().summary().max, to_us(eot_stop));
    // Every step is logged with its time.
    ASSERT_GE(b.host.log().size(), 5u);
    EXPECT_EQ(b.host.log()[1].text, "> ENQ");
    EXPECT_EQ(b.host.log()[2].at, ack_stop);
    EXPECT_EQ(b.host.log()[2].text, "< ACK");
}

TEST(ProtocolHost, NakOnEnqThenRetryAfterBackoff) {
    HostAndFake b(no_wait());
    b.fake.replies[ENQ] = {"\x15"}; // first ENQ refused, then the default ACK
    b.host.send(k_cmd);
    sc_core::sc_start(ms(300));
    const auto enqs = b.fake.times_of(ENQ);
    ASSERT_EQ(enqs.size(), 2u);
    const sc_time nak_stop = enqs[0] + ms(1) + k_char;
    EXPECT_EQ(enqs[1], nak_stop + ms(10) + k_char); // 10 ms x attempt 1
    const auto& c = b.host.counters();
    EXPECT_EQ(c.naks, 1u);
    EXPECT_EQ(c.retries, 1u);
    EXPECT_EQ(c.frames_delivered, 1u);
}

TEST(ProtocolHost, NakOnFrameRetriesWithEnqThenTheWholeFrame) {
    HostAndFake b(no_wait());
    b.fake.replies[ETX] = {"\x15"};
    b.host.send(k_cmd);
    sc_core::sc_start(ms(300));
    EXPECT_EQ(b.fake.bytes(), "\x05" + encode(k_cmd) + "\x05" + encode(k_cmd));
    const auto etx = b.fake.times_of(ETX);
    const auto enqs = b.fake.times_of(ENQ);
    ASSERT_EQ(enqs.size(), 2u);
    EXPECT_EQ(enqs[1], etx[0] + ms(1) + k_char + ms(10) + k_char); // NAK, 10 ms x attempt 1, the ENQ
    EXPECT_EQ(b.host.counters().naks, 1u);
    EXPECT_EQ(b.host.counters().retries, 1u);
    EXPECT_EQ(b.host.counters().frames_delivered, 1u);
}

TEST(ProtocolHost, TimeoutThenRetry) {
    HostAndFake b(no_wait());
    b.fake.replies[ENQ] = {""}; // silent once
    b.host.send(k_cmd);
    sc_core::sc_start(ms(300));
    const auto enqs = b.fake.times_of(ENQ);
    ASSERT_EQ(enqs.size(), 2u);
    // T1 runs from the end of the ENQ to the START bit of an answer, which would be complete one
    // character later: the host gives up then, backs off and sends the ENQ (one more character).
    EXPECT_EQ(enqs[1], enqs[0] + ms(50) + k_char + ms(10) + k_char);
    EXPECT_EQ(b.host.counters().timeouts, 1u);
    EXPECT_EQ(b.host.counters().frames_delivered, 1u);
}

// docs/serial.md "Protocol timers": T1 runs from the end of the ENQ's (ETX's) stop bit to the
// START bit of the answer. The fake answers `delay` after the end of the trigger, so its START
// comes exactly then: 49.9 ms is within T1 for both the ACK and the EOT ...
TEST(ProtocolHost, AnswersStartingWithinT1AreTaken) {
    HostAndFake b(no_wait());
    b.fake.delay = us(49'900);
    b.host.send(k_cmd);
    sc_core::sc_start(ms(400));
    EXPECT_EQ(b.host.counters().timeouts, 0u);
    EXPECT_EQ(b.host.counters().frames_delivered, 1u);
    EXPECT_EQ(b.fake.bytes(), "\x05" + encode(k_cmd)) << "no retry";
}

// ... 50.1 ms is not: for the ACK ...
TEST(ProtocolHost, AckStartingAfterT1IsATimeout) {
    HostAndFake b(no_wait());
    b.fake.delay = us(50'100);
    b.host.send(k_cmd);
    sc_core::sc_start(ms(120));
    EXPECT_GE(b.host.counters().timeouts, 1u);
    EXPECT_EQ(b.host.log()[2].text, "no ACK/NAK within T1");
}

// ... nor for the EOT (the ACK comes after the default 1 ms).
TEST(ProtocolHost, EotStartingAfterT1IsATimeout) {
    HostAndFake b(no_wait());
    b.host.send(k_cmd);
    sc_core::sc_start(ms(5)); // ENQ, ACK; the frame is going out
    b.fake.delay = us(50'100);
    sc_core::sc_start(ms(120));
    EXPECT_GE(b.host.counters().timeouts, 1u);
    bool eot_timeout = false;
    for (const auto& e : b.host.log()) eot_timeout = eot_timeout || e.text == "no EOT/NAK within T1";
    EXPECT_TRUE(eot_timeout);
    EXPECT_EQ(b.host.counters().frames_delivered, 0u);
}

TEST(ProtocolHost, FrameTimeoutStartsOverWithEnq) {
    HostAndFake b(no_wait());
    b.fake.replies[ETX] = {""};
    b.host.send(k_cmd);
    sc_core::sc_start(ms(400));
    EXPECT_EQ(b.fake.bytes(), "\x05" + encode(k_cmd) + "\x05" + encode(k_cmd));
    EXPECT_EQ(b.host.counters().frames_delivered, 1u);
}

TEST(ProtocolHost, GivesUpAfterThreeRetries) {
    HostAndFake b(no_wait());
    b.fake.replies[ENQ] = {"", "", "", "", ""};
    b.host.send(k_cmd);
    sc_core::sc_start(ms(1000));
    const auto enqs = b.fake.times_of(ENQ);
    ASSERT_EQ(enqs.size(), 4u);
    for (unsigned i = 1; i < 4; ++i) EXPECT_EQ(enqs[i], enqs[i - 1] + ms(50) + k_char + ms(10 * i) + k_char) << i;
    const auto& c = b.host.counters();
    EXPECT_EQ(c.frames_failed, 1u);
    EXPECT_EQ(c.retries, 3u);
    EXPECT_EQ(c.timeouts, 4u);
    EXPECT_EQ(c.frames_delivered, 0u);
    EXPECT_TRUE(b.host.idle());
}

TEST(ProtocolHost, AcceptsAControllerFrameWithEot) {
    HostAndFake b;
    const Frame resp{"ST", 0, "1,2,3"};
    b.fake.send_at(ms(1), "\x05");
    b.fake.replies[ACK] = {encode(resp)};
    sc_core::sc_start(ms(200));
    EXPECT_EQ(b.fake.bytes(), "\x06\x04");
    ASSERT_EQ(b.host.responses().size(), 1u);
    EXPECT_EQ(b.host.responses()[0], resp);
    EXPECT_EQ(b.host.counters().responses_received, 1u);
    EXPECT_EQ(b.host.counters().enqs_received, 1u);
}

TEST(ProtocolHost, ReplyDelayIsTheHostsTurnaround) {
    ProtocolHostConfig cfg;
    cfg.timing.reply_delay = ms(3);
    HostAndFake b(cfg);
    b.fake.send_at(ms(1), "\x05");
    b.fake.replies[ACK] = {encode(Frame{"ST", 0, ""})};
    sc_core::sc_start(ms(200));
    const auto acks = b.fake.times_of(ACK);
    ASSERT_EQ(acks.size(), 1u);
    EXPECT_EQ(acks[0], ms(1) + k_char + ms(3) + k_char);
    const auto eots = b.fake.times_of(EOT);
    ASSERT_EQ(eots.size(), 1u);
    // Frame (9 bytes: no data) 1 ms after the ACK, then 3 ms, then the EOT.
    EXPECT_EQ(eots[0], acks[0] + ms(1) + k_char * 9.0 + ms(3) + k_char);
}

TEST(ProtocolHost, BadChecksumIsAnsweredWithNak) {
    HostAndFake b;
    std::string bad = encode(Frame{"ST", 0, "42"});
    bad[bad.size() - 2] ^= 1; // a wrong but well-formed checksum digit
    b.fake.send_at(ms(1), "\x05");
    b.fake.replies[ACK] = {bad};
    sc_core::sc_start(ms(200));
    EXPECT_EQ(b.fake.bytes(), "\x06\x15");
    EXPECT_TRUE(b.host.responses().empty());
    EXPECT_EQ(b.host.counters().naks_sent, 1u);
}

TEST(ProtocolHost, ParityErrorInAFrameIsAnsweredWithNak) {
    HostAndFake b;
    b.fake.send_at(ms(1), "\x05");
    b.fake.replies[ACK] = {encode(Frame{"ST", 0, "42"})};
    b.line.inject(SerialLine::b, 3, FaultKind::flip_data_bit, 7); // the STX: ENQ, SOH, S, T, STX
    sc_core::sc_start(ms(200));
    EXPECT_EQ(b.fake.bytes(), "\x06\x15");
    EXPECT_EQ(b.host.counters().line_errors, 1u);
}

TEST(ProtocolHost, T2GapDropsThePartialFrame) {
    HostAndFake b;
    const std::string f = encode(Frame{"ST", 0, "12345"});
    b.fake.send_at(ms(1), "\x05");
    // After the ACK: half the frame, a 20 ms silence, the rest. T2 runs from one received
    // byte to the next (stop bit to stop bit), as a receiver sees it.
    b.fake.replies[ACK] = {f.substr(0, 6)};
    const sc_time last = ms(2) + k_char * 8.0; // ENQ, ACK, 1 ms, six bytes
    b.fake.send_at(last + ms(20), f.substr(6));  // next byte complete 20 ms + 1 char later
    sc_core::sc_start(ms(300));
    EXPECT_EQ(b.fake.bytes(), "\x06"); // neither EOT nor NAK
    EXPECT_EQ(b.host.counters().frames_dropped, 1u);
    EXPECT_TRUE(b.host.responses().empty());
    bool saw = false;
    for (const auto& e : b.host.log()) saw |= e.text.find("T2 gap after 6 bytes") != std::string::npos;
    EXPECT_TRUE(saw);
}

TEST(ProtocolHost, GapShorterThanT2IsFine) {
    HostAndFake b;
    const std::string f = encode(Frame{"ST", 0, "12345"});
    b.fake.send_at(ms(1), "\x05");
    b.fake.replies[ACK] = {f.substr(0, 6)};
    const sc_time last = ms(2) + k_char * 8.0;
    b.fake.send_at(last + ms(18), f.substr(6)); // complete 18 ms + 1 char after the last: < T2
    sc_core::sc_start(ms(300));
    EXPECT_EQ(b.fake.bytes(), "\x06\x04");
    EXPECT_EQ(b.host.counters().responses_received, 1u);
}

TEST(ProtocolHost, RefusesControllerEnqWhenConfigured) {
    ProtocolHostConfig cfg;
    cfg.nak_enqs = 1;
    HostAndFake b(cfg);
    b.fake.send_at(ms(1), "\x05");
    b.fake.send_at(ms(20), "\x05");
    b.fake.replies[ACK] = {encode(Frame{"ST", 0, ""})};
    sc_core::sc_start(ms(200));
    EXPECT_EQ(b.fake.bytes(), "\x15\x06\x04");
    EXPECT_EQ(b.host.counters().naks_sent, 1u);
    EXPECT_EQ(b.host.counters().responses_received, 1u);
}

TEST(ProtocolHost, EnqCollisionTheExternalSystemWins) {
    HostAndFake b(no_wait());
    // Both sides send ENQ at t = 0. The controller yields: it ACKs ours (after seeing it), and
    // retries its own ENQ when our transaction is over.
    b.host.send(k_cmd);
    b.fake.send_at(sc_core::SC_ZERO_TIME, "\x05");
    const Frame resp{"EC", 0, "hello"};
    b.fake.replies[EOT] = {};
    b.fake.replies[ACK] = {encode(resp)};
    sc_core::sc_start(ms(50));
    // By now the host's command is through; the controller retries.
    b.fake.send_at(ms(60), "\x05");
    sc_core::sc_start(ms(200));
    EXPECT_EQ(b.host.counters().collisions, 1u);
    EXPECT_EQ(b.host.counters().frames_delivered, 1u);
    ASSERT_EQ(b.host.responses().size(), 1u);
    EXPECT_EQ(b.host.responses()[0], resp);
    EXPECT_EQ(b.fake.bytes(), "\x05" + encode(k_cmd) + "\x06\x04");
}

TEST(ProtocolHost, WaitsForTheResponseBeforeTheNextCommand) {
    HostAndFake b; // wait_response on
    b.host.send(k_cmd);
    b.host.send(Frame{"ST", 0, ""});
    // The controller answers the first command 30 ms after the EOT.
    b.fake.replies[ETX] = {"\x04"};
    const sc_time eot_stop = k_char + ms(1) + k_char + k_char * 14.0 + ms(1) + k_char;
    b.fake.send_at(eot_stop + ms(30), "\x05");
    b.fake.replies[ACK] = {encode(Frame{"EC", 0, "hello"})};
    sc_core::sc_start(ms(400));
    const auto enqs = b.fake.times_of(ENQ);
    ASSERT_EQ(enqs.size(), 2u);
    const auto eots = b.fake.times_of(EOT);
    ASSERT_EQ(eots.size(), 1u); // the host's EOT to the response
    EXPECT_EQ(enqs[1], eots[0] + k_char); // next command right after the response is accepted
    ASSERT_EQ(b.host.response_us().count(), 1u);
}

TEST(ProtocolHost, ResponseTimeoutReleasesTheNextCommand) {
    ProtocolHostConfig cfg;
    cfg.traffic.response_timeout = ms(100);
    HostAndFake b(cfg);
    b.host.send(k_cmd);
    b.host.send(k_cmd);
    sc_core::sc_start(ms(400));
    const auto enqs = b.fake.times_of(ENQ);
    ASSERT_EQ(enqs.size(), 2u);
    const sc_time eot_stop = k_char + ms(1) + k_char + k_char * 14.0 + ms(1) + k_char;
    EXPECT_EQ(enqs[1], eot_stop + ms(100) + k_char);
    EXPECT_EQ(b.host.counters().response_timeouts, 2u - (b.host.idle() ? 0u : 1u));
}

// ---- traffic ---------------------------------------------------------------------------------

TEST(HostTraffic, FixedRate) {
    ProtocolHostConfig cfg = no_wait();
    cfg.traffic.pattern = HostTraffic::Pattern::fixed;
    cfg.traffic.rate = 20; // every 50 ms
    cfg.traffic.count = 4;
    cfg.traffic.start = ms(5);
    HostAndFake b(cfg);
    sc_core::sc_start(ms(400));
    const auto enqs = b.fake.times_of(ENQ);
    ASSERT_EQ(enqs.size(), 4u);
    for (unsigned i = 0; i < 4; ++i) EXPECT_EQ(enqs[i], ms(5 + 50 * i) + k_char);
    EXPECT_EQ(b.host.counters().frames_delivered, 4u);
}

TEST(HostTraffic, SaturateSendsAsFastAsTheLineAllows) {
    ProtocolHostConfig cfg = no_wait();
    cfg.traffic.pattern = HostTraffic::Pattern::saturate;
    cfg.traffic.count = 3;
    cfg.traffic.data_size = 5;
    cfg.traffic.start = ms(7);
    HostAndFake b(cfg);
    b.fake.delay = sc_core::SC_ZERO_TIME;
    sc_core::sc_start(ms(400));
    const auto enqs = b.fake.times_of(ENQ);
    const auto eots = b.host.counters().frames_delivered;
    ASSERT_EQ(enqs.size(), 3u);
    EXPECT_EQ(enqs[0], ms(7) + k_char);
    EXPECT_EQ(eots, 3u);
    // One command = ENQ, ACK, 14-byte frame, EOT: 17 characters back to back.
    EXPECT_EQ(enqs[1] - enqs[0], k_char * 17.0);
    EXPECT_EQ(enqs[2] - enqs[1], k_char * 17.0);
}

TEST(HostTraffic, PoissonIsSeededAndNearTheRate) {
    ProtocolHostConfig cfg = no_wait();
    cfg.traffic.pattern = HostTraffic::Pattern::poisson;
    cfg.traffic.rate = 2; // mean 500 ms; a command takes ~22 ms
    cfg.traffic.data_size = 0;
    cfg.traffic.seed = 99;
    HostAndFake b(cfg);
    sc_core::sc_start(sc_time(200, sc_core::SC_SEC));
    const double n = static_cast<double>(b.host.counters().frames_sent);
    EXPECT_GT(n, 400 * 0.85);
    EXPECT_LT(n, 400 * 1.15);
    EXPECT_EQ(b.host.counters().frames_delivered, b.host.counters().frames_sent - (b.host.idle() ? 0 : 1));
}

TEST(HostTraffic, BurstsQueueSeveralCommandsAtOnce) {
    ProtocolHostConfig cfg = no_wait();
    cfg.traffic.pattern = HostTraffic::Pattern::burst;
    cfg.traffic.burst_size = 3;
    cfg.traffic.burst_period = ms(500);
    cfg.traffic.count = 6;
    cfg.traffic.data_size = 5;
    HostAndFake b(cfg);
    b.fake.delay = sc_core::SC_ZERO_TIME;
    sc_core::sc_start(ms(1000));
    const auto enqs = b.fake.times_of(ENQ);
    ASSERT_EQ(enqs.size(), 6u);
    EXPECT_EQ(enqs[0], k_char);
    EXPECT_EQ(enqs[2], k_char + k_char * 34.0); // back to back within a burst
    EXPECT_EQ(enqs[3], ms(500) + k_char);
}

TEST(HostTraffic, RandomSizesAndTokenMix) {
    ProtocolHostConfig cfg = no_wait();
    cfg.format = SerialFormat::rs232(115200);
    cfg.traffic.pattern = HostTraffic::Pattern::saturate;
    cfg.traffic.count = 40;
    cfg.traffic.random_size = true;
    cfg.traffic.data_size = 300;
    cfg.traffic.tokens = {{"EC", 3.0}, {"ST", 1.0}};
    HostAndFake b(cfg);
    b.fake.fmt = cfg.format;
    b.fake.delay = sc_core::SC_ZERO_TIME;
    sc_core::sc_start(sc_time(10, sc_core::SC_SEC));
    EXPECT_EQ(b.host.counters().frames_delivered, 40u);
    // Decode what the controller received.
    std::string all = b.fake.bytes();
    std::size_t ec = 0, st = 0, max_len = 0, min_len = 1000;
    for (std::size_t p = all.find('\x01'); p != std::string::npos; p = all.find('\x01', p + 1)) {
        const std::size_t e = all.find('\x03', p);
        Frame f;
        ASSERT_EQ(decode(all.substr(p, e - p + 1), f), "");
        (f.token == "EC" ? ec : st)++;
        max_len = std::max(max_len, f.data.size());
        min_len = std::min(min_len, f.data.size());
    }
    EXPECT_EQ(ec + st, 40u);
    EXPECT_GT(ec, st);
    EXPECT_GT(st, 0u);
    EXPECT_LE(max_len, 300u);
    EXPECT_LT(min_len, max_len);
}

TEST(HostTraffic, BadConfigurationIsNamed) {
    auto message = [](ProtocolHostConfig c) {
        try {
            c.validate();
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    ProtocolHostConfig c1;
    c1.traffic.pattern = HostTraffic::Pattern::fixed;
    c1.traffic.rate = 0;
    EXPECT_NE(message(c1).find("rate 0"), std::string::npos);
    ProtocolHostConfig c2;
    c2.traffic.data_size = 9000;
    EXPECT_NE(message(c2).find("9000"), std::string::npos);
    ProtocolHostConfig c3;
    c3.traffic.tokens = {{"XYZ", 1.0}};
    EXPECT_NE(message(c3).find("'XYZ'"), std::string::npos);
    EXPECT_THROW(HostTraffic::parse_pattern("sometimes"), std::invalid_argument);
}
