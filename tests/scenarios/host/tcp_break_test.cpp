// BREAK through the tcp host: the telnet-style escape (scenarios/host/telnet.h) and TcpHost with
// `telnet` on and off, over 127.0.0.1 with an ephemeral port. Every wait is bounded.
#include "models/clock.h"
#include "scenarios/host/tcp_host.h"
#include "scenarios/host/telnet.h"
#include "tests/support/sc_test.h"
#include "tests/scenarios/host/tcp_test_util.h"

#include <string>
#include <thread>
#include <vector>

using namespace rcsim;
using namespace rcsim::test;
using sc_core::sc_time;

namespace {

/// Decodes `in` and writes each data byte as itself and each BREAK as "<BRK>".
std::string decode(const std::string& in) {
    TelnetDecoder d;
    std::string out;
    for (unsigned char b : in) {
        std::uint8_t data = 0;
        switch (d.feed(b, data)) {
        case TelnetDecoder::Out::byte: out += static_cast<char>(data); break;
        case TelnetDecoder::Out::brk: out += "<BRK>"; break;
        case TelnetDecoder::Out::none: break;
        }
    }
    return out;
}

/// The controller end: characters and BREAK edges with their times; sends `script` at 9600,8E1.
class ControllerEnd : public sc_core::sc_module, public SerialEndpoint {
public:
    SerialFormat fmt = SerialFormat::rs232(9600);
    std::string script; // sent at 1 ms
    std::vector<std::pair<sc_time, std::uint8_t>> got;
    std::vector<std::pair<sc_time, bool>> breaks;

    ControllerEnd(sc_core::sc_module_name n, SerialLine& line) : sc_module(n), line_(line) {
        line.attach(SerialLine::a, *this);
        spawn_checked([this] { run(); }, "run");
    }
    SerialFormat rx_format() const override { return fmt; }
    void rx_char(const SerialRx& c) override { got.emplace_back(c.start, static_cast<std::uint8_t>(c.data)); }
    void rx_break(bool active) override { breaks.emplace_back(sc_core::sc_time_stamp(), active); }

private:
    SerialLine& line_;
    void run() {
        wait(us(1000));
        for (unsigned char b : script) {
            line_.transmit(SerialLine::a, SerialWord::encode(b, fmt));
            wait(fmt.frame_time());
        }
    }
};

} // namespace

TEST(TelnetDecoder, PassesDataAndTakesOutCommands) {
    EXPECT_EQ(decode("ABC"), "ABC");
    EXPECT_EQ(decode("A\xff\xf3" "B"), "A<BRK>B");     // IAC BRK
    EXPECT_EQ(decode("\xff\xff"), "\xff");               // IAC IAC: one data 255
    EXPECT_EQ(decode("\xff\xfb\x01X"), "X");             // IAC WILL ECHO: negotiation, ignored
    EXPECT_EQ(decode("\xff\xfd\x03Y"), "Y");             // IAC DO SUPPRESS-GO-AHEAD
    EXPECT_EQ(decode("\xff\xfa\x2c\x01\xff\xff\xff\xf0Z"), "Z"); // IAC SB ... (IAC IAC inside) IAC SE
    EXPECT_EQ(decode("\xff\xf1Q"), "Q");                 // IAC NOP: dropped
}

TEST(TelnetDecoder, EscapeDoublesEveryIac) {
    const std::vector<std::uint8_t> in{0x41, 0xFF, 0x42, 0xFF, 0xFF};
    const std::vector<std::uint8_t> want{0x41, 0xFF, 0xFF, 0x42, 0xFF, 0xFF, 0xFF, 0xFF};
    EXPECT_EQ(telnet_escape(in), want);
    EXPECT_EQ(decode(std::string(want.begin(), want.end())), std::string(in.begin(), in.end()));
}

// With `telnet`, IAC BRK holds the wire at SPACE for break_duration: the controller's receiver
// detects it one of its characters (11 bits of 9600) after the fall and its end at the release;
// the next character starts when the BREAK ends. A 255 the controller sends arrives doubled.
TEST(TcpHostTelnet, IacBrkIsABreakOnTheLineAndIacIsDoubled) {
    SerialLine line("line");
    TcpHostConfig cfg;
    cfg.telnet = true;
    cfg.break_duration = us(20000);
    cfg.end_on_disconnect = true;
    TcpHost host("tcp", cfg);
    host.connect(line, SerialLine::b);
    ControllerEnd ctl("ctl", line);
    ctl.script = "\xff";
    Watchdog wd("wd", milliseconds(10000));
    std::string from_controller;
    std::thread client([&] {
        Client c;
        if (!c.connect(host.port())) return;
        from_controller = c.take(2);
        c.send("A\xff\xf3" "B\xff\xff");
        std::this_thread::sleep_for(milliseconds(100));
        c.close();
    });
    sc_core::sc_start();
    client.join();
    EXPECT_FALSE(wd.fired);
    EXPECT_EQ(from_controller, "\xff\xff");
    ASSERT_EQ(ctl.got.size(), 3u);
    EXPECT_EQ(ctl.got[0].second, 'A');
    EXPECT_EQ(ctl.got[1].second, 'B');
    EXPECT_EQ(ctl.got[2].second, 0xFF);
    ASSERT_EQ(ctl.breaks.size(), 2u);
    EXPECT_TRUE(ctl.breaks[0].second);
    EXPECT_FALSE(ctl.breaks[1].second);
    const sc_time fall = ctl.got[0].first + cfg.format.frame_time(); // after A's frame
    EXPECT_EQ(ctl.breaks[0].first, fall + cfg.format.receive_time());
    EXPECT_EQ(ctl.breaks[1].first, fall + us(20000));
    EXPECT_EQ(ctl.got[1].first, fall + us(20000)); // B's START at the release
    EXPECT_EQ(host.counters().breaks_sent, 1u);
}

// Without `telnet` the stream is plain bytes: 255 243 are two characters, no BREAK.
TEST(TcpHostTelnet, WithoutTelnetIacBrkIsTwoCharacters) {
    SerialLine line("line");
    TcpHostConfig cfg;
    cfg.end_on_disconnect = true;
    TcpHost host("tcp", cfg);
    host.connect(line, SerialLine::b);
    ControllerEnd ctl("ctl", line);
    Watchdog wd("wd", milliseconds(10000));
    std::thread client([&] {
        Client c;
        if (!c.connect(host.port())) return;
        c.send("\xff\xf3");
        std::this_thread::sleep_for(milliseconds(100));
        c.close();
    });
    sc_core::sc_start();
    client.join();
    EXPECT_FALSE(wd.fired);
    ASSERT_EQ(ctl.got.size(), 2u);
    EXPECT_EQ(ctl.got[0].second, 0xFF);
    EXPECT_EQ(ctl.got[1].second, 0xF3);
    EXPECT_TRUE(ctl.breaks.empty());
    EXPECT_EQ(host.counters().breaks_sent, 0u);
}
