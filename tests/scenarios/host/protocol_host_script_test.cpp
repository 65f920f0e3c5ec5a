// The protocol host's script mode (docs/scenarios.md "Scripted hosts") against a fake controller
// that answers every command with a response frame: steps in order, each after the previous
// response; expect_bch; wait_state polling ST; delay and at_ms; a failed step stops the script.
#include "scenarios/host/protocol_host.h"

#include "models/clock.h"
#include "tests/support/sc_test.h"

#include <deque>
#include <functional>

using namespace rcsim;
using namespace rcsim::proto;
using sc_core::sc_time;

namespace {

/// Answers ENQ with ACK and a command frame with EOT, then 2 ms later sends ENQ and, 5 ms after
/// that (the host's ACK takes one character, 1.15 ms), the response `respond(command)`.
struct Responder : sc_core::sc_module, SerialEndpoint {
    SerialFormat fmt = SerialFormat::rs232(9600);
    SerialLine& line;
    std::string rx;                 // bytes of the command being received
    std::vector<Frame> commands;    // every command received, in order
    std::vector<sc_time> etx_at;    // the stop bit of each command's ETX
    std::function<Frame(const Frame&)> respond;
    std::deque<std::pair<sc_time, std::string>> outbox;
    sc_core::sc_event wake;

    Responder(sc_core::sc_module_name n, SerialLine& l) : sc_module(n), line(l) {
        line.attach(SerialLine::b, *this);
        respond = [](const Frame& c) { return Frame{c.token, 0, c.data}; };
        test::spawn_forever([this] { sender(); }, "sender");
    }
    void send_at(const sc_time& at, const std::string& b) {
        outbox.emplace_back(at, b);
        wake.notify(sc_core::SC_ZERO_TIME);
    }
    void sender() {
        for (;;) {
            if (outbox.empty()) {
                wait(wake);
                continue;
            }
            const sc_time now = sc_core::sc_time_stamp();
            if (outbox.front().first > now) {
                wait(outbox.front().first - now, wake);
                continue;
            }
            const std::string b = outbox.front().second;
            outbox.pop_front();
            for (unsigned char c : b) {
                line.transmit(SerialLine::b, SerialWord::encode(c, fmt));
                wait(fmt.frame_time());
            }
        }
    }
    SerialFormat rx_format() const override { return fmt; }
    void rx_char(const SerialRx& c) override {
        const auto b = static_cast<std::uint8_t>(c.data);
        const sc_time now = sc_core::sc_time_stamp();
        if (b == ENQ) return send_at(now + ms(1), "\x06");
        if (b == SOH) rx.clear();
        rx += static_cast<char>(b);
        if (b != ETX) return;
        Frame f;
        if (!decode(rx, f).empty()) return send_at(now + ms(1), "\x15");
        commands.push_back(f);
        etx_at.push_back(c.stop);
        send_at(now + ms(1), "\x04");
        send_at(now + ms(3), "\x05");
        send_at(now + ms(8), encode(respond(f)));
    }
    void rx_break(bool) override {}
};

struct HostAndResponder {
    SerialLine line{"line"};
    ProtocolHost host;
    Responder fake{"fake", line};
    explicit HostAndResponder(const ProtocolHostConfig& cfg) : host("host", cfg) { host.connect(line, SerialLine::a); }
};

ScriptStep command(const std::string& token, const std::string& data, int expect_bch = -1, int line = 0) {
    ScriptStep s;
    s.token = token, s.data = data, s.expect_bch = expect_bch, s.line = line;
    return s;
}
ScriptStep wait_state(const std::string& state, sc_time timeout, int line = 0) {
    ScriptStep s;
    s.kind = ScriptStep::Kind::wait_state;
    s.token = "ST", s.state = state, s.poll = ms(10), s.timeout = timeout, s.line = line;
    return s;
}
ProtocolHostConfig scripted(std::vector<ScriptStep> steps) {
    ProtocolHostConfig c;
    c.traffic.pattern = HostTraffic::Pattern::script;
    c.traffic.script = std::move(steps);
    return c;
}

} // namespace

TEST(ProtocolHostScript, StepsRunInOrderEachAfterItsResponse) {
    HostAndResponder b(scripted({command("EC", "one", 0), command("PW", "1,2", 0), command("EC", "three", 0)}));
    sc_core::sc_start(ms(500));
    const ScriptResult& r = b.host.script_result();
    EXPECT_TRUE(r.done()) << r.failure;
    EXPECT_EQ(r.completed, 3u);
    ASSERT_EQ(b.fake.commands.size(), 3u);
    EXPECT_EQ(b.fake.commands[0], (Frame{"EC", 0, "one"}));
    EXPECT_EQ(b.fake.commands[1], (Frame{"PW", 0, "1,2"}));
    // The second command's ENQ follows the first response: its frame cannot start before the
    // response's ETX, 8 ms after the first command's ETX plus the response's own characters.
    ASSERT_EQ(b.fake.etx_at.size(), 3u);
    const sc_time resp = ms(8) + SerialFormat::rs232(9600).frame_time() * double(encode(Frame{"EC", 0, "one"}).size());
    EXPECT_GT(b.fake.etx_at[1], b.fake.etx_at[0] + resp);
    ASSERT_EQ(r.commands.size(), 3u);
    EXPECT_EQ(r.commands[2].token, "EC");
    EXPECT_EQ(r.commands[2].bch, 0);
    EXPECT_EQ(r.commands[0].etx, b.fake.etx_at[0]); // the host's ETX time is the line's
}

TEST(ProtocolHostScript, WrongBchFailsTheStepAndStopsTheScript) {
    HostAndResponder b(scripted({command("EC", "a", 0, 11), command("XX", "", 0, 12), command("EC", "never", -1, 13)}));
    b.fake.respond = [](const Frame& c) { return Frame{c.token, c.token == "XX" ? std::uint8_t{1} : std::uint8_t{0}, ""}; };
    sc_core::sc_start(ms(500));
    const ScriptResult& r = b.host.script_result();
    EXPECT_TRUE(r.failed);
    EXPECT_FALSE(r.done());
    EXPECT_EQ(r.completed, 1u);
    EXPECT_EQ(r.failed_step, 1u);
    EXPECT_EQ(r.failed_line, 12);
    EXPECT_NE(r.failure.find("XX answered BCH 01"), std::string::npos) << r.failure;
    EXPECT_EQ(b.fake.commands.size(), 2u) << "the step after the failed one is not sent";
}

TEST(ProtocolHostScript, WaitStatePollsStUntilTheState) {
    HostAndResponder b(scripted({wait_state("STANDSTILL", ms(1000)), command("EC", "after", 0)}));
    int polls = 0;
    b.fake.respond = [&polls](const Frame& c) {
        if (c.token != "ST") return Frame{c.token, 0, c.data};
        return Frame{"ST", 0, ++polls < 3 ? "DISABLED,IDLE,,0,0" : "STANDSTILL,IDLE,,0,0"};
    };
    sc_core::sc_start(ms(1000));
    EXPECT_TRUE(b.host.script_result().done()) << b.host.script_result().failure;
    ASSERT_EQ(b.fake.commands.size(), 4u); // three ST, then the command
    EXPECT_EQ(b.fake.commands[2].token, "ST");
    EXPECT_EQ(b.fake.commands[3], (Frame{"EC", 0, "after"}));
    EXPECT_TRUE(b.host.script_result().commands.size() == 1u) << "ST polls are not script commands";
}

TEST(ProtocolHostScript, WaitStateTimesOut) {
    HostAndResponder b(scripted({wait_state("STANDSTILL", ms(200), 7)}));
    b.fake.respond = [](const Frame&) { return Frame{"ST", 0, "DISABLED,IDLE,"}; };
    sc_core::sc_start(ms(1000));
    const ScriptResult& r = b.host.script_result();
    EXPECT_TRUE(r.failed);
    EXPECT_EQ(r.failed_line, 7);
    EXPECT_NE(r.failure.find("state STANDSTILL not reached within 200.000 ms (last ST: DISABLED)"), std::string::npos)
        << r.failure;
    // Each poll is a round trip of at least 8 ms plus 10 ms between polls: a handful, not hundreds.
    EXPECT_GE(b.fake.commands.size(), 2u);
    EXPECT_LE(b.fake.commands.size(), 200u / 18u + 1u);
}

TEST(ProtocolHostScript, AtAndDelayHoldTheNextStep) {
    ScriptStep pause;
    pause.kind = ScriptStep::Kind::delay;
    pause.duration = ms(100);
    ScriptStep late = command("EC", "late");
    late.at = ms(300);
    HostAndResponder b(scripted({command("EC", "now"), pause, command("EC", "then"), late}));
    sc_core::sc_start(ms(800));
    ASSERT_TRUE(b.host.script_result().done()) << b.host.script_result().failure;
    ASSERT_EQ(b.fake.etx_at.size(), 3u);
    // "then" starts 100 ms after "now"'s response (which came within 30 ms of its ETX).
    EXPECT_GT(b.fake.etx_at[1], b.fake.etx_at[0] + ms(100));
    EXPECT_LT(b.fake.etx_at[1], b.fake.etx_at[0] + ms(100) + ms(60));
    EXPECT_GT(b.fake.etx_at[2], ms(300));
}

TEST(ProtocolHostScript, WaitNoneGoesOnAtTheEot) {
    ScriptStep a = command("EC", "a");
    a.wait_response = false;
    HostAndResponder b(scripted({a, command("EC", "b")}));
    b.fake.respond = [](const Frame& c) { return Frame{c.token, 0, c.data}; };
    sc_core::sc_start(ms(500));
    EXPECT_TRUE(b.host.script_result().done());
    ASSERT_EQ(b.host.script_result().commands.size(), 2u);
    EXPECT_EQ(b.host.script_result().commands[0].bch, -1); // no response awaited
    EXPECT_EQ(b.host.script_result().commands[1].bch, 0);
}

TEST(ProtocolHostScript, ConfigRejectsAScriptWithoutThePatternAndBadFrames) {
    ProtocolHostConfig c = scripted({});
    EXPECT_THROW(c.validate(), std::invalid_argument);
    c = scripted({command("EC", "x")});
    c.traffic.pattern = HostTraffic::Pattern::saturate;
    EXPECT_THROW(c.validate(), std::invalid_argument);
    c = scripted({command("E", "x")});
    EXPECT_THROW(c.validate(), std::invalid_argument);
    c = scripted({command("EC", "\x01")});
    EXPECT_THROW(c.validate(), std::invalid_argument);
    EXPECT_NO_THROW(scripted({command("EC", "x")}).validate());
}
