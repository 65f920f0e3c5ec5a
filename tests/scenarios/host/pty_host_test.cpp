// PtyHost against a scripted controller end, with a termios client in the test (the end-to-end
// tests with pyserial and the real firmware are pty_*.py). Every wait is bounded: a watchdog
// pauses a run that went wrong, and client reads poll with deadlines.
#include "models/clock.h"
#include "models/plumbing/config_error.h"
#include "scenarios/host/pty_host.h"
#include "scenarios/host/tcp_host.h"
#include "tests/support/sc_test.h"
#include "tests/support/files.h"
#include "tests/scenarios/host/tcp_test_util.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

using namespace rcsim;
using namespace rcsim::test;
using sc_core::sc_time;

namespace {

std::string temp_path(const std::string& name) { return (scratch_dir() / name).string(); }

/// A program on the slave side, as pyserial would be: open, tcsetattr, write, read.
class TermClient {
public:
    explicit TermClient(const std::string& path) : fd_(::open(path.c_str(), O_RDWR | O_NOCTTY)) {}
    ~TermClient() { close(); }
    bool ok() const { return fd_ >= 0; }
    void close() {
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
    }
    termios attr() const {
        termios t{};
        ::tcgetattr(fd_, &t);
        return t;
    }
    void set_speed(speed_t s) {
        termios t = attr();
        ::cfsetispeed(&t, s);
        ::cfsetospeed(&t, s);
        ::tcsetattr(fd_, TCSANOW, &t);
    }
    void write(const std::string& bytes) {
        if (::write(fd_, bytes.data(), bytes.size()) != static_cast<ssize_t>(bytes.size())) ADD_FAILURE() << "write";
    }
    /// Reads `n` bytes or what came within `timeout`.
    std::string read(std::size_t n, milliseconds timeout = milliseconds(3000)) {
        std::string got;
        const auto end = WallClock::now() + timeout;
        while (got.size() < n && WallClock::now() < end) {
            pollfd p{fd_, POLLIN, 0};
            if (::poll(&p, 1, 50) <= 0) continue;
            char buf[64];
            const ssize_t k = ::read(fd_, buf, std::min(sizeof buf, n - got.size()));
            if (k > 0) got.append(buf, static_cast<std::size_t>(k));
        }
        return got;
    }

private:
    int fd_;
};

/// The controller's end of the line: records characters with their error flags and BREAK
/// edges, and sends `script` (time, bytes) in its own format.
class ControllerEnd : public sc_core::sc_module, public SerialEndpoint {
public:
    SerialFormat fmt = SerialFormat::rs232(9600);
    std::vector<std::pair<sc_time, std::string>> script;
    /// If set, script entry i is also held until ready(i) holds (polled every simulated
    /// millisecond, a wall millisecond under the pacer): a client thread's step that must come
    /// first, which a loaded host may delay past any fixed time.
    std::function<bool(std::size_t)> ready;
    std::vector<SerialRx> got;
    std::vector<std::pair<sc_time, bool>> breaks;

    ControllerEnd(sc_core::sc_module_name n, SerialLine& line) : sc_module(n), line_(line) {
        line.attach(SerialLine::a, *this);
        spawn_checked([this] { run(); }, "run");
    }
    SerialFormat rx_format() const override { return fmt; }
    void rx_char(const SerialRx& c) override { got.push_back(c); }
    void rx_break(bool active) override { breaks.emplace_back(sc_core::sc_time_stamp(), active); }

private:
    SerialLine& line_;
    void run() {
        for (std::size_t i = 0; i < script.size(); ++i) {
            const auto& s = script[i];
            if (s.first > sc_core::sc_time_stamp()) wait(s.first - sc_core::sc_time_stamp());
            while (ready && !ready(i)) wait(sc_time(1, sc_core::SC_MS));
            for (unsigned char b : s.second) {
                line_.transmit(SerialLine::a, SerialWord::encode(b, fmt));
                wait(fmt.frame_time());
            }
        }
    }
};

/// Waits (wall time, bounded) until `cond` holds: a client's step that must follow the host's.
bool wait_until(const std::function<bool()>& cond, milliseconds limit = milliseconds(10000)) {
    const auto end = WallClock::now() + limit;
    while (!cond() && WallClock::now() < end) std::this_thread::sleep_for(milliseconds(1));
    return cond();
}

/// One paced run while `client` runs on its own thread, until the client has returned and
/// `settled()` holds (what its last step must cause on the line), then `tail` more simulated
/// time for what must not follow; polled every simulated millisecond. A fixed simulated length
/// would race a client thread that a loaded host runs late. The watchdog ends a run that hangs.
void run_until_client_done(const std::function<void()>& client, const std::function<bool()>& settled = {},
                           const sc_time& tail = sc_core::SC_ZERO_TIME) {
    RealtimePacer pacer("pacer", 1.0);
    Watchdog wd("wd", milliseconds(10000));
    std::atomic<bool> done{false};
    spawn_checked(
        [&] {
            while (!done || (settled && !settled())) wait(sc_time(1, sc_core::SC_MS));
            if (tail > sc_core::SC_ZERO_TIME) wait(tail);
            sc_core::sc_pause();
        },
        "until_client_done");
    std::thread t([&] {
        client();
        done = true;
    });
    sc_core::sc_start();
    t.join();
    EXPECT_FALSE(wd.fired);
}

} // namespace

TEST(PtyTermios, StandardRatesMapBothWays) {
    EXPECT_EQ(termios_speed(9600), static_cast<unsigned>(B9600));
    EXPECT_EQ(termios_speed(300), static_cast<unsigned>(B300));
    EXPECT_EQ(termios_speed(115200), static_cast<unsigned>(B115200));
    EXPECT_EQ(termios_baud(B4800), 4800u);
    EXPECT_EQ(termios_baud(B50), 50u);
    EXPECT_EQ(termios_speed(9601), static_cast<unsigned>(B0)); // not a termios rate
    EXPECT_EQ(termios_baud(B0), 0u);
}

// A NUL's SPACE: START and the data bits, plus the parity bit when it is 0 (even and space parity
// of zero ones; odd and mark parity put a 1 there).
TEST(PtyTermios, TheSpaceOfANulCountsAZeroParityBit) {
    EXPECT_EQ(nul_space(SerialFormat::parse("9600,8E1")), ratio_time(10, 9600));
    EXPECT_EQ(nul_space(SerialFormat::parse("9600,8O1")), ratio_time(9, 9600));
    EXPECT_EQ(nul_space(SerialFormat::parse("9600,8N1")), ratio_time(9, 9600));
    EXPECT_EQ(nul_space(SerialFormat::parse("300,7S2")), ratio_time(9, 300));
}

TEST(PtyHost, OpensARawSlaveAtThePortsRateBehindTheLinkAndRemovesTheLink) {
    const std::string link = temp_path("rcsim_pty_link");
    std::string slave;
    {
        SerialLine line("line");
        PtyHostConfig cfg;
        cfg.format = SerialFormat::parse("4800,8E2");
        cfg.link = link;
        PtyHost host("pty", cfg);
        host.connect(line, SerialLine::b);
        slave = host.slave_path();
        EXPECT_EQ(slave.rfind("/dev/pts/", 0), 0u) << slave;
        EXPECT_EQ(std::filesystem::read_symlink(link).string(), slave);
        EXPECT_EQ(host.path(), link);
        TermClient c(link);
        ASSERT_TRUE(c.ok());
        const termios t = c.attr();
        EXPECT_EQ(::cfgetospeed(&t), static_cast<speed_t>(B4800));
        EXPECT_TRUE(t.c_cflag & CSTOPB); // 2 stop bits
        EXPECT_FALSE(t.c_lflag & (ICANON | ECHO | ISIG));
        EXPECT_FALSE(t.c_oflag & OPOST);
        EXPECT_EQ(host.client_format().describe(), "4800,8E2");
    }
    struct stat st {};
    EXPECT_NE(::lstat(link.c_str(), &st), 0) << "the link outlived the host";
}

TEST(PtyHost, ALinkPathHoldingAFileIsAConfigErrorAndTheFileStays) {
    const std::string path = temp_path("rcsim_pty_file");
    std::ofstream(path) << "mine\n";
    PtyHostConfig cfg;
    cfg.link = path;
    EXPECT_THROW(PtyHost("pty", cfg), ConfigError);
    std::ifstream in(path);
    std::string text;
    std::getline(in, text);
    EXPECT_EQ(text, "mine");
    std::remove(path.c_str());
}

TEST(PtyHost, AStaleLinkOfAnEarlierRunIsReplaced) {
    const std::string link = temp_path("rcsim_pty_stale");
    std::filesystem::remove(link);
    std::filesystem::create_symlink("/dev/pts/does-not-exist", link);
    SerialLine line("line");
    PtyHostConfig cfg;
    cfg.link = link;
    PtyHost host("pty", cfg);
    host.connect(line, SerialLine::b);
    EXPECT_EQ(std::filesystem::read_symlink(link).string(), host.slave_path());
}

// The client's baud rate is the host side's: at 4800 a 4800 receiver reads the bytes clean, one
// 4800 frame (11 bits at 8E1) apart. Had the host used the port's 9600 the receiver would see
// each START edge half as long and garbage after it.
TEST(PtyHost, ClientBytesGoOnTheLineAtTheClientsBaudRate) {
    SerialLine line("line");
    PtyHost host("pty", PtyHostConfig{});
    host.connect(line, SerialLine::b);
    ControllerEnd ctl("ctl", line);
    ctl.fmt = SerialFormat::parse("4800,8E1");
    run_until_client_done(
        [&] {
            TermClient c(host.slave_path());
            c.set_speed(B4800);
            c.write("AB");
        },
        [&] { return ctl.got.size() >= 2; }, us(50000));
    ASSERT_EQ(ctl.got.size(), 2u);
    EXPECT_EQ(ctl.got[0].data, 'A');
    EXPECT_EQ(ctl.got[1].data, 'B');
    for (const SerialRx& r : ctl.got) EXPECT_FALSE(r.parity_error || r.framing_error);
    EXPECT_EQ(ctl.got[1].start - ctl.got[0].start, ratio_time(11, 4800));
    EXPECT_EQ(host.counters().bytes_sent, 2u);
}

// A 9600 controller sends 'T' (0x54) to a client set to 4800,8E1. The 4800 receiver samples the
// 9600 cells 1, 3, 5, ...: START = cell 1 (data bit 0 = 0), data = cells 3, 5, 7 (bits 2, 4, 6:
// 1, 1, 1), cell 9 (parity: 3 ones, even -> 1), cell 11 (STOP), then idle MARK: 0xFF, whose
// even parity bit should be 0 but reads 1 (the MARK of the idle line): a parity error.
// Each 'T' waits for the client's rate to be set (the host takes the rate at the START edge).
TEST(PtyHost, ControllerBytesAreSampledAtTheClientsBaudRate) {
    SerialLine line("line");
    PtyHost host("pty", PtyHostConfig{});
    host.connect(line, SerialLine::b);
    ControllerEnd ctl("ctl", line);
    ctl.script = {{us(100000), "T"}, {us(200000), "T"}};
    std::atomic<std::size_t> rates_set{0};
    ctl.ready = [&](std::size_t i) { return rates_set > i; };
    std::string slow, fast;
    run_until_client_done([&] {
        TermClient c(host.slave_path());
        c.set_speed(B4800);
        ++rates_set;
        slow = c.read(1, milliseconds(10000));
        c.set_speed(B9600);
        ++rates_set;
        fast = c.read(1, milliseconds(10000));
    });
    EXPECT_EQ(slow, "\xFF");
    EXPECT_EQ(fast, "T");
    EXPECT_EQ(host.counters().line_errors, 1u);
    // The io thread counts a write when it completes, which may be just after the client read
    // the byte: wait for the count to come (a count above 2 still fails below).
    wait_until([&] { return host.counters().bytes_out >= 2; });
    EXPECT_EQ(host.counters().bytes_out, 2u);
}

// A NUL at 300,8E1 holds the wire at SPACE for 10 bits of 300 (33.3 ms), far beyond one 9600,8E1
// character (11 bits of 9600, 1.146 ms): the controller's receiver detects a BREAK one of its
// characters after the fall and its end when the wire returns to MARK. The same NUL at 9600 is an
// ordinary character. The host takes the client's rate with each byte: the client changes it
// once the host has taken the first NUL, and keeps it until the host has taken the second.
TEST(PtyHost, ASlowNulIsABreakOnTheLine) {
    SerialLine line("line");
    PtyHost host("pty", PtyHostConfig{});
    host.connect(line, SerialLine::b);
    ControllerEnd ctl("ctl", line);
    run_until_client_done(
        [&] {
            TermClient c(host.slave_path());
            c.write(std::string(1, '\0'));
            EXPECT_TRUE(wait_until([&] { return host.counters().bytes_in >= 1; }));
            c.set_speed(B300);
            c.write(std::string(1, '\0'));
            EXPECT_TRUE(wait_until([&] { return host.counters().bytes_in >= 2; }));
        },
        [&] { return ctl.breaks.size() >= 2; }, us(50000));
    ASSERT_EQ(ctl.got.size(), 1u);
    EXPECT_EQ(ctl.got[0].data, 0u);
    EXPECT_FALSE(ctl.got[0].parity_error || ctl.got[0].framing_error);
    ASSERT_EQ(ctl.breaks.size(), 2u);
    EXPECT_TRUE(ctl.breaks[0].second);
    EXPECT_FALSE(ctl.breaks[1].second);
    EXPECT_EQ(ctl.breaks[1].first - ctl.breaks[0].first, ratio_time(10, 300) - ratio_time(11, 9600));
    EXPECT_EQ(host.counters().breaks_sent, 1u);
    EXPECT_EQ(host.counters().bytes_sent, 1u);
}

// tcsendbreak on a Linux pty reaches the master as nothing (the pty driver has no break_ctl):
// the host sees no byte and puts nothing on the line. If a kernel ever forwards it, this test
// says so and the docs must change.
TEST(PtyHost, TcsendbreakOnALinuxPtyReachesTheHostAsNothing) {
    SerialLine line("line");
    PtyHost host("pty", PtyHostConfig{});
    host.connect(line, SerialLine::b);
    ControllerEnd ctl("ctl", line);
    run_until_client_done(
        [&] {
            const int fd = ::open(host.slave_path().c_str(), O_RDWR | O_NOCTTY);
            EXPECT_EQ(::tcsendbreak(fd, 0), 0); // "succeeds"
            ::close(fd);
        },
        {}, us(300000)); // time for anything it sent to arrive
    EXPECT_EQ(host.counters().bytes_in, 0u);
    EXPECT_TRUE(ctl.breaks.empty());
    EXPECT_TRUE(ctl.got.empty());
}

// With end_on_disconnect the run ends once the last client closed, after its bytes are on the
// line; the opens and closes are counted. The client closes once the host has its bytes: the host
// reads a closing client's bytes for kCloseSettle only, which a loaded host can exceed.
TEST(PtyHost, TheLastCloseEndsTheRunAfterTheClientsBytes) {
    SerialLine line("line");
    PtyHostConfig cfg;
    cfg.end_on_disconnect = true;
    PtyHost host("pty", cfg);
    host.connect(line, SerialLine::b);
    ControllerEnd ctl("ctl", line);
    RealtimePacer pacer("pacer", 1.0);
    Watchdog wd("wd", milliseconds(10000));
    std::thread client([&] {
        TermClient c(host.slave_path());
        c.write("XYZ");
        EXPECT_TRUE(wait_until([&] { return host.counters().bytes_in >= 3; }));
    });
    sc_core::sc_start(); // until the client closes
    client.join();
    EXPECT_FALSE(wd.fired);
    EXPECT_TRUE(host.ended());
    EXPECT_EQ(sc_core::sc_get_status(), sc_core::SC_PAUSED);
    ASSERT_EQ(ctl.got.size(), 3u);
    EXPECT_EQ(ctl.got[2].data, 'Z');
    EXPECT_EQ(host.counters().connections, 1u);
    EXPECT_EQ(host.counters().disconnects, 1u);
}
