// TcpHost, RealtimePacer and ReplayHost against a scripted serial peer, over 127.0.0.1 with an
// ephemeral port. Every wait is bounded; a watchdog pauses a run that went wrong.
#include "models/clock.h"
#include "models/plumbing/config_error.h"
#include "scenarios/host/replay_host.h"
#include "scenarios/host/tcp_host.h"
#include "tests/support/sc_test.h"
#include "tests/support/files.h"
#include "tests/scenarios/host/tcp_test_util.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

using namespace rcsim;
using namespace rcsim::test;
using sc_core::sc_time;

namespace {

double wall_since(WallClock::time_point t0) { return std::chrono::duration<double>(WallClock::now() - t0).count(); }

std::string temp_path(const std::string& name) { return (scratch_dir() / name).string(); }

} // namespace

TEST(TcpListen, ParsesHostAndPort) {
    TcpHostConfig c;
    c.set_listen("127.0.0.1:5510");
    EXPECT_EQ(c.address, "127.0.0.1");
    EXPECT_EQ(c.port, 5510u);
    c.set_listen(":0");
    EXPECT_EQ(c.address, "127.0.0.1");
    EXPECT_EQ(c.port, 0u);
    c.set_listen("[::1]:7");
    EXPECT_EQ(c.address, "::1");
    EXPECT_THROW(c.set_listen("5510"), std::invalid_argument);
    EXPECT_THROW(c.set_listen("127.0.0.1:70000"), std::invalid_argument);
    EXPECT_THROW(c.set_listen("localhost:1"), std::invalid_argument); // numeric addresses only
    EXPECT_THROW(c.set_listen("127.0.0.1:x"), std::invalid_argument);
}

TEST(TcpHost, EphemeralPortIsBoundAndWrittenToThePortFile) {
    SerialLine line("line");
    TcpHostConfig cfg;
    cfg.port_file = temp_path("rcsim_tcp_port");
    TcpHost host("tcp", cfg);
    host.connect(line, SerialLine::b);
    EXPECT_NE(host.port(), 0);
    std::ifstream pf(cfg.port_file);
    unsigned p = 0;
    pf >> p;
    EXPECT_EQ(p, host.port());
    EXPECT_EQ(host.endpoint(), "127.0.0.1:" + std::to_string(host.port()));
    std::remove(cfg.port_file.c_str());
}

TEST(TcpHost, ABusyPortIsAConfigError) {
    SerialLine line("line");
    TcpHost first("first", TcpHostConfig{});
    first.connect(line, SerialLine::b);
    TcpHostConfig cfg;
    cfg.port = first.port();
    EXPECT_THROW(TcpHost("second", cfg), ConfigError);
}

// The controller talks before anybody listens: its bytes wait and reach the client once it
// connects. Then the client's byte goes the other way and its disconnect ends the run.
TEST(TcpHost, BytesSentBeforeTheClientConnectsAreDeliveredAfterItConnects) {
    SerialLine line("line");
    TcpHostConfig cfg;
    cfg.end_on_disconnect = true;
    TcpHost host("tcp", cfg);
    host.connect(line, SerialLine::b);
    Peer peer("peer", line, SerialLine::a);
    peer.script = {{us(1000), "HELLO"}};
    RealtimePacer pacer("pacer", 100.0); // keeps time moving while nobody is connected
    Watchdog wd("wd", milliseconds(10000));

    sc_core::sc_start(us(20000));
    EXPECT_EQ(host.counters().bytes_buffered, 5u);
    EXPECT_EQ(host.counters().bytes_out, 0u);

    std::string got;
    std::thread client([&] {
        Client c;
        if (!c.connect(host.port())) return;
        got = c.take(5);
        c.send("X");
        c.close();
    });
    sc_core::sc_start(); // until the client disconnects
    client.join();
    EXPECT_FALSE(wd.fired);
    EXPECT_EQ(got, "HELLO");
    EXPECT_EQ(peer.text(), "X");
    EXPECT_TRUE(host.ended());
    const auto c = host.counters();
    EXPECT_EQ(c.connections, 1u);
    EXPECT_EQ(c.disconnects, 1u);
    EXPECT_EQ(c.bytes_out, 5u);
    EXPECT_EQ(c.bytes_in, 1u);
    EXPECT_EQ(c.bytes_sent, 1u);
}

// Nothing in the model has a timed event: only the suspending attach keeps the kernel waiting
// for the idle client instead of ending by starvation at time 0.
TEST(TcpHost, KernelDoesNotStarveWhileAClientIsConnectedAndIdle) {
    SerialLine line("line");
    TcpHostConfig cfg;
    cfg.end_on_disconnect = true;
    TcpHost host("tcp", cfg);
    host.connect(line, SerialLine::b);
    Peer peer("peer", line, SerialLine::a);
    peer.echo = true;
    Watchdog wd("wd", milliseconds(10000));

    std::string echoed;
    std::thread client([&] {
        Client c;
        if (!c.connect(host.port())) return;
        std::this_thread::sleep_for(milliseconds(300)); // idle
        c.send("A");
        echoed = c.take(1);
        c.close();
    });
    const auto t0 = WallClock::now();
    sc_core::sc_start();
    const double wall = wall_since(t0);
    client.join();
    EXPECT_FALSE(wd.fired);
    EXPECT_GE(wall, 0.25);
    EXPECT_EQ(echoed, "A");
    EXPECT_EQ(peer.text(), "A");
    EXPECT_TRUE(host.ended());
    EXPECT_EQ(sc_core::sc_get_status(), sc_core::SC_PAUSED);
}

// A burst from the socket goes on the wire one character per frame time, like a real terminal.
TEST(TcpHost, InputIsWireAccurateOneCharacterPerFrameTime) {
    SerialLine line("line");
    TcpHostConfig cfg;
    cfg.end_on_disconnect = true;
    cfg.format = SerialFormat::parse("9600,8E1");
    TcpHost host("tcp", cfg);
    host.connect(line, SerialLine::b);
    Peer peer("peer", line, SerialLine::a);
    Watchdog wd("wd", milliseconds(10000));
    std::thread client([&] {
        Client c;
        if (!c.connect(host.port())) return;
        c.send("ABCDEFGH");
        std::this_thread::sleep_for(milliseconds(100));
        c.close();
    });
    sc_core::sc_start();
    client.join();
    EXPECT_FALSE(wd.fired);
    ASSERT_EQ(peer.text(), "ABCDEFGH");
    const sc_time frame = cfg.format.frame_time();
    for (std::size_t i = 1; i < peer.got.size(); ++i) EXPECT_EQ(peer.got[i].first - peer.got[i - 1].first, frame) << i;
}

// Without end_on_disconnect the host serves the next client, and output produced between
// clients waits for it.
TEST(TcpHost, ServesTheNextClientAfterADisconnect) {
    SerialLine line("line");
    TcpHost host("tcp", TcpHostConfig{});
    host.connect(line, SerialLine::b);
    Peer peer("peer", line, SerialLine::a);
    peer.echo = true;
    RealtimePacer pacer("pacer", 1.0);
    std::string first, second;
    std::thread client([&] {
        {
            Client c;
            if (!c.connect(host.port())) return;
            c.send("1");
            first = c.take(1);
        }
        std::this_thread::sleep_for(milliseconds(50));
        Client c;
        if (!c.connect(host.port())) return;
        c.send("2");
        second = c.take(1);
    });
    sc_core::sc_start(us(1000000)); // one paced second; the client is done well before
    client.join();
    EXPECT_EQ(first, "1");
    EXPECT_EQ(second, "2");
    EXPECT_EQ(host.counters().connections, 2u);
}

TEST(RealtimePacer, KeepsSimulatedTimeWithinWallTimeTimesTheFactor) {
    for (const double rtf : {1.0}) {
        RealtimePacer pacer("pacer", rtf);
        const auto t0 = WallClock::now();
        double worst_lead = 0;
        // Sample the bound every 10 ms of simulated time while it runs.
        for (int i = 0; i < 30; ++i) {
            sc_core::sc_start(us(10000));
            const double sim = sc_core::sc_time_stamp().to_seconds();
            worst_lead = std::max(worst_lead, sim - wall_since(t0) * rtf);
        }
        const double wall = wall_since(t0);
        EXPECT_LE(worst_lead, 0.050);
        EXPECT_GE(wall, 0.3 / rtf - 0.05);
        EXPECT_LT(wall, 30.0); // it does not stall
        EXPECT_GT(pacer.stats().naps, 0u);
        EXPECT_LE(pacer.stats().max_lead_s, 0.050);
    }
}

TEST(RealtimePacer, AFasterFactorRunsFaster) {
    RealtimePacer pacer("pacer", 4.0);
    const auto t0 = WallClock::now();
    sc_core::sc_start(us(400000));
    const double wall = wall_since(t0);
    EXPECT_LE(0.4, wall * 4.0 + 0.05);
    EXPECT_LT(wall, 20.0);
}

TEST(SessionLog, RoundTripsAndNamesTheLineOfABadEntry) {
    const std::string path = temp_path("rcsim_session.log");
    {
        SessionLogWriter w;
        w.open(path, SerialFormat::parse("19200,7O2"));
        w.event(us(0), SessionEvent::Kind::listen, "127.0.0.1:1234");
        w.event(us(5), SessionEvent::Kind::connect);
        w.in(us(10), 0x05);
        w.out(us(20), 0x06, true, false);
        w.event(us(30), SessionEvent::Kind::end);
    }
    const SessionLog log = read_session_log(path);
    ASSERT_TRUE(log.format.has_value());
    EXPECT_EQ(log.format->describe(), SerialFormat::parse("19200,7O2").describe());
    ASSERT_EQ(log.events.size(), 5u);
    EXPECT_EQ(log.events[0].text, "127.0.0.1:1234");
    EXPECT_EQ(log.events[2].kind, SessionEvent::Kind::in);
    EXPECT_EQ(log.events[2].at, us(10));
    EXPECT_EQ(log.events[2].byte, 0x05);
    EXPECT_EQ(log.events[3].kind, SessionEvent::Kind::out);
    EXPECT_TRUE(log.events[3].parity_error);
    EXPECT_FALSE(log.events[3].framing_error);
    EXPECT_EQ(log.events[4].kind, SessionEvent::Kind::end);

    std::ofstream(path, std::ios::app) << "40000000 in ZZ\n";
    try {
        read_session_log(path);
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find(":8:"), std::string::npos) << e.what();
    }
    std::ofstream(path, std::ios::trunc) << "format 9600,8E1\n100 in 05\n50 in 06\n";
    EXPECT_THROW(read_session_log(path), ConfigError);
    std::remove(path.c_str());
}

namespace {
// A log for an echoing peer: bytes in at 1 ms and 5 ms; each comes back one receive time after
// the peer got it (the peer answers at the end of the stop bit).
std::string echo_log(std::uint8_t second_out) {
    const SerialFormat f = SerialFormat::rs232(9600);
    const sc_time r = f.receive_time();
    const std::string path = temp_path("rcsim_replay_in.log");
    SessionLogWriter w;
    w.open(path, f);
    w.in(us(1000), 'A');
    w.out(us(1000) + r + r, 'A', false, false);
    w.in(us(5000), 'B');
    w.out(us(5000) + r + r, second_out, false, false);
    w.event(us(9000), SessionEvent::Kind::end);
    return path;
}
} // namespace

TEST(ReplayHost, FeedsTheLogAtTheRecordedTimesAndMatchesTheAnswers) {
    SerialLine line("line");
    ReplayHostConfig cfg;
    cfg.file = echo_log('B');
    cfg.end_at_log_end = true;
    cfg.record_path = temp_path("rcsim_replay_out.log");
    ReplayHost host("replay", cfg);
    host.connect(line, SerialLine::b);
    Peer peer("peer", line, SerialLine::a);
    peer.echo = true;
    sc_core::sc_start();
    EXPECT_EQ(sc_core::sc_time_stamp(), us(9000)); // paused at the log's end
    ASSERT_EQ(peer.got.size(), 2u);
    const sc_time r = SerialFormat::rs232(9600).receive_time();
    EXPECT_EQ(peer.got[0].first, us(1000) + r);
    EXPECT_EQ(peer.got[1].first, us(5000) + r);
    EXPECT_EQ(host.counters().out_matched, 2u);
    EXPECT_EQ(host.counters().out_mismatched, 0u);
    EXPECT_EQ(host.out_missing(), 0u);
    EXPECT_EQ(host.first_mismatch(), "");
    // Re-recording the replay gives the same in/out events.
    const SessionLog a = read_session_log(cfg.file), b = read_session_log(cfg.record_path);
    ASSERT_EQ(a.events.size(), b.events.size());
    for (std::size_t i = 0; i < a.events.size(); ++i) {
        EXPECT_EQ(a.events[i].kind, b.events[i].kind) << i;
        EXPECT_EQ(a.events[i].at, b.events[i].at) << i;
        EXPECT_EQ(a.events[i].byte, b.events[i].byte) << i;
    }
    std::remove(cfg.file.c_str());
    std::remove(cfg.record_path.c_str());
}

TEST(ReplayHost, ReportsTheFirstDifferentAnswer) {
    SerialLine line("line");
    ReplayHostConfig cfg;
    cfg.file = echo_log('Z'); // the recorded session got 'Z' back; the echo now says 'B'
    cfg.end_at_log_end = true;
    ReplayHost host("replay", cfg);
    host.connect(line, SerialLine::b);
    Peer peer("peer", line, SerialLine::a);
    peer.echo = true;
    sc_core::sc_start();
    EXPECT_EQ(host.counters().out_matched, 1u);
    EXPECT_EQ(host.counters().out_mismatched, 1u);
    EXPECT_NE(host.first_mismatch().find("expected 5A"), std::string::npos) << host.first_mismatch();
    EXPECT_NE(host.first_mismatch().find("got 42"), std::string::npos) << host.first_mismatch();
    std::remove(cfg.file.c_str());
}
