// The TCP host on the assembled controller running the real communication firmware: a client on
// 127.0.0.1 speaks the ENQ/ACK/SOH..ETX protocol to it at real time; a recorded session replays
// to the same bytes at the same simulated times. Every wait is bounded.
#include "models/clock.h"
#include "models/plumbing/config_error.h"
#include "scenarios/board/controller.h"
#include "models/serial_line.h"
#include "models/frame_codec.h"
#include "models/plumbing/output_file.h"
#include "scenarios/host/tcp_host.h"
#include "scenarios/run/runner.h"
#include "scenarios/config/scenario.h"
#include "tests/support/sc_test.h"
#include "tests/support/files.h"
#include "tests/scenarios/host/tcp_test_util.h"

#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace rcsim;
using namespace rcsim::test;
namespace fs = std::filesystem;

namespace {

const std::string kEnq(1, '\x05'), kAck(1, '\x06'), kEot(1, '\x04');

/// What the client saw of one EC transaction.
struct Exchange {
    bool connected = false;
    std::string ack, eot, enq, response;
    proto::Frame frame;
    std::string decode_error = "not received";
};

/// The host side of docs/system.md §5 by hand, as a user's script would do it: ENQ, ACK?, frame,
/// EOT?; then the controller's ENQ, our ACK, its response frame, our EOT.
Exchange ec_exchange(unsigned short port, const std::string& data) {
    Exchange x;
    Client c;
    x.connected = c.connect(port);
    if (!x.connected) return x;
    std::this_thread::sleep_for(milliseconds(150)); // the firmware programs its 82510 (~20 ms sim)
    c.send(kEnq);
    x.ack = c.take(1);
    c.send(proto::encode(proto::Frame{"EC", 0, data}));
    x.eot = c.take(1);
    x.enq = c.take(1, milliseconds(5000)); // the controller's own ENQ for the response
    if (x.enq == kEnq) {
        c.send(kAck);
        x.response = c.take_through('\x03', milliseconds(5000));
        x.decode_error = proto::decode(x.response, x.frame);
        c.send(kEot);
    }
    std::this_thread::sleep_for(milliseconds(100)); // let the EOT reach the controller
    c.close();
    return x;
}

std::string hex(const std::string& s) {
    std::ostringstream o;
    for (unsigned char ch : s) o << proto::hex2(ch) << ' ';
    return o.str();
}

} // namespace

TEST(TcpSystem, AClientTalksToTheRealFirmwareAtRealTime) {
    Controller ctl("ctl");
    SerialLine line("line0"), idle1("line1"), idle2("line2");
    ctl.comm.load_rom(RCSIM_COMM_FW_ROM);
    ctl.comm.uart[0].connect(line, SerialLine::a);
    ctl.comm.uart[1].connect(idle1, SerialLine::a);
    ctl.comm.uart[2].connect(idle2, SerialLine::a);
    TcpHostConfig cfg;
    cfg.end_on_disconnect = true;
    TcpHost host("tcp", cfg);
    host.connect(line, SerialLine::b);
    RealtimePacer pacer("pacer", 1.0);
    Watchdog wd("wd", milliseconds(30000));

    Exchange x;
    std::thread client([&] { x = ec_exchange(host.port(), "HELLO WORLD"); });
    const auto t0 = WallClock::now();
    sc_core::sc_start(); // until the client disconnects
    const double wall = std::chrono::duration<double>(WallClock::now() - t0).count();
    client.join();

    EXPECT_FALSE(wd.fired);
    ASSERT_TRUE(x.connected);
    EXPECT_EQ(x.ack, kAck) << hex(x.ack);
    EXPECT_EQ(x.eot, kEot) << hex(x.eot);
    EXPECT_EQ(x.enq, kEnq) << hex(x.enq);
    EXPECT_EQ(x.decode_error, "") << hex(x.response);
    EXPECT_EQ(x.frame.token, "EC");
    EXPECT_EQ(x.frame.data, "HELLO WORLD");
    EXPECT_TRUE(host.ended());
    EXPECT_EQ(ctl.comm.uart[0].stats().overruns, 0u);
    EXPECT_EQ(ctl.main.port_stats(0).frames_received, 1u);
    // Paced: simulated time never ran ahead of wall time by more than a step.
    EXPECT_LE(sc_core::sc_time_stamp().to_seconds(), wall * 1.0 + 0.05);
}

namespace {

/// The in/out lines of a session log (times and bytes), without connect/listen/end.
std::vector<std::string> traffic(const fs::path& p) {
    std::vector<std::string> v;
    for (const SessionEvent& e : read_session_log(p.string()).events)
        if (e.kind == SessionEvent::Kind::in || e.kind == SessionEvent::Kind::out)
            v.push_back(std::to_string(e.at.value()) + (e.kind == SessionEvent::Kind::in ? " in " : " out ") +
                        proto::hex2(e.byte));
    return v;
}

/// Runs `fn` in a child process (one SystemC simulation per process) and returns its exit code;
/// the child is killed after `limit`.
int in_child(const std::function<int()>& fn, milliseconds limit) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        int rc = 99;
        try {
            rc = fn();
        } catch (const std::exception& e) {
            std::fprintf(stderr, "child: %s\n", e.what());
        }
        std::fflush(nullptr);
        ::_exit(rc);
    }
    const auto end = WallClock::now() + limit;
    int status = 0;
    while (::waitpid(pid, &status, WNOHANG) == 0) {
        if (WallClock::now() > end) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &status, 0);
            return -1;
        }
        std::this_thread::sleep_for(milliseconds(20));
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -2;
}

} // namespace

// rcsim run with `host: tcp` and `record:`; the recorded session is replayed with `host: replay`
// and draws the same answers at the same simulated times, ending at the same time. The run's
// outputs (port file, session logs) land in its --out folder; the replay reads the live one's.
TEST(TcpSystem, ARecordedSessionReplaysToTheSameBytesAtTheSameTimes) {
    const fs::path dir = test::scratch_dir();
    write_file(dir / "live.yaml", "name: live\nduration_s: 0\nrealtime: 1.0\nports:\n"
                                  "  - {host: tcp, listen: \"127.0.0.1:0\", format: \"9600,8E1\", "
                                  "port_file: port.txt, record: session.log}\n");
    write_file(dir / "replay.yaml", "name: replay\nduration_s: 0\nports:\n"
                                    "  - {host: replay, file: live/session.log, record: replayed.log}\n");

    const int live_rc = in_child(
        [&] {
            Exchange x;
            std::thread client([&] {
                // The port file appears when the scenario's tcp host has bound its port.
                const auto end = WallClock::now() + milliseconds(10000);
                while (!fs::exists(dir / "live" / "port.txt") && WallClock::now() < end)
                    std::this_thread::sleep_for(milliseconds(10));
                unsigned port = 0;
                std::ifstream(dir / "live" / "port.txt") >> port;
                if (port) x = ec_exchange(static_cast<unsigned short>(port), "REPLAY ME");
            });
            RunOptions opt;
            opt.out_dir = (dir / "live").string();
            nlohmann::json report;
            const int rc = run_scenario(load_scenario((dir / "live.yaml").string()), opt, report);
            client.join();
            if (x.decode_error != "" || x.frame.data != "REPLAY ME") return 10;
            return rc;
        },
        milliseconds(60000));
    ASSERT_EQ(live_rc, 0) << "the live session failed";

    const auto recorded = traffic(dir / "live" / "session.log");
    ASSERT_GT(recorded.size(), 20u);

    RunOptions opt;
    opt.out_dir = (dir / "replay").string();
    nlohmann::json report;
    const int rc = run_scenario(load_scenario((dir / "replay.yaml").string()), opt, report);
    EXPECT_EQ(rc, 0) << report["checks"].dump();
    const auto& r = report["ports"][0]["replay"];
    EXPECT_EQ(r["out_mismatched"].get<std::uint64_t>(), 0u) << r.dump();
    EXPECT_EQ(r["out_missing"].get<std::uint64_t>(), 0u) << r.dump();
    EXPECT_GT(r["out_matched"].get<std::uint64_t>(), 10u) << r.dump();
    EXPECT_EQ(traffic(dir / "replay" / "replayed.log"), recorded);

    nlohmann::json live;
    std::ifstream(dir / "live" / "report.json") >> live;
    EXPECT_EQ(report["sim_time_s"], live["sim_time_s"]);
    EXPECT_EQ(report["ports"][0]["chars_received"], live["ports"][0]["chars_received"]);
    EXPECT_EQ(report["ports"][0]["main_cpu_frames_received"], 1u);
    fs::remove_all(dir);
}

TEST(TcpSystem, DurationZeroNeedsATcpOrReplayHost) {
    const fs::path dir = test::scratch_dir();
    write_file(dir / "bad.yaml", "duration_s: 0\nports:\n  - {host: raw}\n");
    EXPECT_THROW(load_scenario((dir / "bad.yaml").string()), ConfigError);
    write_file(dir / "bad2.yaml", "ports:\n  - {host: tcp, listen: \"127.0.0.1:99999\"}\n");
    EXPECT_THROW(load_scenario((dir / "bad2.yaml").string()), ConfigError);
    write_file(dir / "bad3.yaml", "ports:\n  - {host: replay}\n");
    EXPECT_THROW(load_scenario((dir / "bad3.yaml").string()), ConfigError);
    fs::remove_all(dir);
}
