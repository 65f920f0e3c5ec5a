// Test helpers for the TCP host: a blocking loopback client with deadlines, a serial peer, and a
// watchdog that stops a run that went wrong (through async_request_update, the thread-safe way).
#pragma once

#include "models/serial_line.h"
#include "tests/support/sc_test.h"

#include <systemc>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace rcsim::test {

using WallClock = std::chrono::steady_clock;
using std::chrono::milliseconds;

/// A TCP client on 127.0.0.1; every wait is bounded.
class Client {
public:
    /// Connects, retrying until `timeout` (the listener exists before the test starts, so this
    /// normally succeeds at once).
    bool connect(unsigned short port, milliseconds timeout = milliseconds(5000)) {
        const auto end = WallClock::now() + timeout;
        while (WallClock::now() < end) {
            fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
            sockaddr_in a{};
            a.sin_family = AF_INET;
            a.sin_port = htons(port);
            a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
            if (::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
                int one = 1;
                ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
                return true;
            }
            ::close(fd_);
            fd_ = -1;
            std::this_thread::sleep_for(milliseconds(20));
        }
        return false;
    }
    ~Client() { close(); }
    void close() {
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
    }
    bool send(const std::string& bytes) {
        std::size_t done = 0;
        while (done < bytes.size()) {
            const auto n = ::send(fd_, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
            if (n <= 0) return false;
            done += static_cast<std::size_t>(n);
        }
        return true;
    }
    /// Reads until `done(buffer)` holds, the peer closes, or `timeout` passes.
    std::string read_until(const std::function<bool(const std::string&)>& done, milliseconds timeout) {
        const auto end = WallClock::now() + timeout;
        while (!done(buf_)) {
            const auto left = std::chrono::duration_cast<milliseconds>(end - WallClock::now()).count();
            if (left <= 0) break;
            pollfd p{fd_, POLLIN, 0};
            if (::poll(&p, 1, static_cast<int>(std::min<long long>(left, 100))) <= 0) continue;
            char tmp[256];
            const auto n = ::recv(fd_, tmp, sizeof tmp, 0);
            if (n <= 0) break;
            buf_.append(tmp, static_cast<std::size_t>(n));
        }
        return buf_;
    }
    /// Reads `n` bytes (or what came within `timeout`) and takes them out of the buffer.
    std::string take(std::size_t n, milliseconds timeout = milliseconds(3000)) {
        read_until([n](const std::string& b) { return b.size() >= n; }, timeout);
        std::string out = buf_.substr(0, std::min(n, buf_.size()));
        buf_.erase(0, out.size());
        return out;
    }
    /// Reads through the first occurrence of `c` and takes it out of the buffer.
    std::string take_through(char c, milliseconds timeout = milliseconds(3000)) {
        read_until([c](const std::string& b) { return b.find(c) != std::string::npos; }, timeout);
        const auto at = buf_.find(c);
        std::string out = at == std::string::npos ? buf_ : buf_.substr(0, at + 1);
        buf_.erase(0, out.size());
        return out;
    }

private:
    int fd_ = -1;
    std::string buf_;
};

/// The controller end of a line for unit tests: records what it receives, optionally echoes
/// it, and transmits scripted strings at given times.
class Peer : public sc_core::sc_module, public SerialEndpoint {
public:
    SerialFormat fmt = SerialFormat::rs232(9600);
    bool echo = false;
    std::vector<std::pair<sc_core::sc_time, std::string>> script;
    std::vector<std::pair<sc_core::sc_time, std::uint8_t>> got;

    Peer(sc_core::sc_module_name n, SerialLine& line, SerialLine::Side side) : sc_module(n), line_(line), side_(side) {
        line.attach(side, *this);
        spawn_checked([this] { run(); }, "run");
    }
    std::string text() const {
        std::string s;
        for (const auto& g : got) s += static_cast<char>(g.second);
        return s;
    }
    SerialFormat rx_format() const override { return fmt; }
    void rx_char(const SerialRx& c) override {
        got.emplace_back(c.stop, static_cast<std::uint8_t>(c.data));
        if (echo) line_.transmit(side_, SerialWord::encode(c.data, fmt));
    }
    void rx_break(bool) override {}

private:
    SerialLine& line_;
    SerialLine::Side side_;
    void run() {
        for (const auto& s : script) {
            if (s.first > sc_core::sc_time_stamp()) wait(s.first - sc_core::sc_time_stamp());
            for (unsigned char b : s.second) {
                line_.transmit(side_, SerialWord::encode(b, fmt));
                wait(fmt.frame_time());
            }
        }
    }
};

/// Pauses the simulation if it is still running `limit` after construction (wall time), so a
/// broken run fails its assertions instead of hanging until the ctest TIMEOUT.
class Watchdog : public sc_core::sc_module {
public:
    bool fired = false;
    SC_HAS_PROCESS(Watchdog);
    Watchdog(sc_core::sc_module_name n, milliseconds limit) : sc_module(n), door_("door") {
        SC_METHOD(on_fire);
        sensitive << door_.ev;
        dont_initialize();
        thread_ = std::thread([this, limit] {
            std::unique_lock<std::mutex> lock(mu_);
            if (!cv_.wait_for(lock, limit, [this] { return cancelled_; })) door_.async_request_update();
        });
    }
    ~Watchdog() override {
        {
            std::lock_guard<std::mutex> lock(mu_);
            cancelled_ = true;
        }
        cv_.notify_all();
        thread_.join();
    }

private:
    struct Door : sc_core::sc_prim_channel {
        explicit Door(const char* n) : sc_prim_channel(n) {}
        sc_core::sc_event ev;
        using sc_prim_channel::async_request_update;
        void update() override { ev.notify(sc_core::SC_ZERO_TIME); }
    } door_;
    std::mutex mu_;
    std::condition_variable cv_;
    bool cancelled_ = false;
    std::thread thread_;
    void on_fire() {
        fired = true;
        sc_core::sc_pause();
    }
};

} // namespace rcsim::test
