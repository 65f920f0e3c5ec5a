// rcsim — pseudo-terminal serial backend (see pty_host.h).
#include "scenarios/host/pty_host.h"

#include "models/plumbing/config_error.h"

#include <fcntl.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <utility>

namespace rcsim {

namespace asio = boost::asio;

namespace {

// The standard termios rates (termios(3); Linux adds the ones above 38400).
constexpr std::pair<speed_t, std::uint64_t> kSpeeds[] = {
    {B50, 50},           {B75, 75},           {B110, 110},         {B150, 150},         {B200, 200},
    {B300, 300},         {B600, 600},         {B1200, 1200},       {B1800, 1800},       {B2400, 2400},
    {B4800, 4800},       {B9600, 9600},       {B19200, 19200},     {B38400, 38400},     {B57600, 57600},
    {B115200, 115200},   {B230400, 230400},   {B460800, 460800},   {B500000, 500000},   {B576000, 576000},
    {B921600, 921600},   {B1000000, 1000000}, {B1152000, 1152000}, {B1500000, 1500000}, {B2000000, 2000000},
    {B2500000, 2500000}, {B3000000, 3000000}, {B3500000, 3500000}, {B4000000, 4000000},
};

std::string errno_text() { return std::strerror(errno); }

} // namespace

unsigned termios_speed(std::uint64_t bps) {
    for (const auto& [speed, rate] : kSpeeds)
        if (rate == bps) return speed;
    return B0;
}

std::uint64_t termios_baud(unsigned speed) {
    for (const auto& [s, rate] : kSpeeds)
        if (s == speed) return rate;
    return 0;
}

sc_core::sc_time nul_space(const SerialFormat& f) {
    const bool zero_parity = f.parity != Parity::none && !parity_bit(0, f.data_bits, f.parity);
    return f.bit.span(2 * (1 + f.data_bits + (zero_parity ? 1 : 0)));
}

// ---------------------------------------------------------------------------------------------
// SystemC side

PtyHost::PtyHost(sc_core::sc_module_name name, const PtyHostConfig& cfg)
    : sc_module(name), cfg_(cfg), inbox_(sc_core::sc_gen_unique_name("inbox")), out_(cfg.max_buffer),
      master_(io_), watch_(io_), settle_(io_) {
    cfg_.format.validate();
    try {
        open_pty();
        make_link();
    } catch (...) {
        if (slave_fd_ >= 0) ::close(slave_fd_);
        throw;
    }
    SC_HAS_PROCESS(PtyHost);
    SC_THREAD(run);
    start_read();
    start_watch();
    thread_ = std::thread([this] { io_.run(); });
}

PtyHost::~PtyHost() {
    stopping_ = true;
    io_.stop();
    if (thread_.joinable()) thread_.join();
    if (attached_) inbox_.async_detach_suspending();
    if (linked_) {
        // Only our own link: a later run may have replaced it with its own meanwhile.
        char target[PATH_MAX];
        const ssize_t n = ::readlink(cfg_.link.c_str(), target, sizeof target - 1);
        if (n > 0 && std::string(target, static_cast<std::size_t>(n)) == slave_path_) ::unlink(cfg_.link.c_str());
    }
    if (slave_fd_ >= 0) ::close(slave_fd_);
}

void PtyHost::open_pty() {
    const std::string me = name();
    const int master = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (master < 0) throw ConfigError(me + ": cannot open a pseudo-terminal: " + errno_text());
    master_.assign(master); // closed with master_ from here on
    char slave[PATH_MAX];
    if (::grantpt(master) != 0 || ::unlockpt(master) != 0 || ::ptsname_r(master, slave, sizeof slave) != 0)
        throw ConfigError(me + ": cannot unlock the pseudo-terminal: " + errno_text());
    slave_path_ = slave;
    slave_fd_ = ::open(slave, O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (slave_fd_ < 0) throw ConfigError(me + ": cannot open " + slave_path_ + ": " + errno_text());
    // Raw, as a serial port a program opens is expected to be: no echo back into the simulated
    // line, no line editing, no CR/LF translation. The port's baud rate and stop bits, so a
    // client that never calls tcsetattr (cat, echo >) talks at the port's rate.
    termios t{};
    if (::tcgetattr(slave_fd_, &t) != 0) throw ConfigError(me + ": tcgetattr " + slave_path_ + ": " + errno_text());
    ::cfmakeraw(&t);
    t.c_cflag |= CLOCAL | CREAD;
    if (cfg_.format.stop_halves > 2) t.c_cflag |= CSTOPB;
    const speed_t speed = termios_speed(static_cast<std::uint64_t>(cfg_.format.bit.bps() + 0.5));
    if (speed != B0) {
        ::cfsetispeed(&t, speed);
        ::cfsetospeed(&t, speed);
    }
    if (::tcsetattr(slave_fd_, TCSANOW, &t) != 0)
        throw ConfigError(me + ": tcsetattr " + slave_path_ + ": " + errno_text());
    // Watched after the host's own open, so only clients' opens and closes are seen.
    const int watch = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (watch < 0 || ::inotify_add_watch(watch, slave, IN_OPEN | IN_CLOSE) < 0) {
        const std::string why = errno_text();
        if (watch >= 0) ::close(watch);
        throw ConfigError(me + ": cannot watch " + slave_path_ + " (inotify): " + why);
    }
    watch_.assign(watch);
}

void PtyHost::make_link() {
    if (cfg_.link.empty()) return;
    const std::string& link = cfg_.link;
    struct stat st {};
    // A symlink left by an earlier run is replaced; anything else is the user's and stays.
    if (::lstat(link.c_str(), &st) == 0 && !S_ISLNK(st.st_mode))
        throw ConfigError(link, 0, "cannot make the pty link: the path exists and is not a symlink");
    // Made beside it and renamed into place, so a client polling for the link never sees a
    // half-made one.
    const std::string tmp = link + ".tmp" + std::to_string(::getpid());
    ::unlink(tmp.c_str());
    if (::symlink(slave_path_.c_str(), tmp.c_str()) != 0 || ::rename(tmp.c_str(), link.c_str()) != 0) {
        const std::string why = errno_text();
        ::unlink(tmp.c_str());
        throw ConfigError(link, 0, "cannot make the pty link: " + why);
    }
    linked_ = true;
}

SerialFormat PtyHost::client_format() const {
    SerialFormat f = cfg_.format;
    termios t{};
    if (::tcgetattr(slave_fd_, &t) != 0) return f;
    if (const std::uint64_t bps = termios_baud(::cfgetospeed(&t))) f.bit = BitTime::baud(bps);
    f.stop_halves = (t.c_cflag & CSTOPB) ? 4 : 2;
    return f;
}

PtyHost::Counters PtyHost::counters() const { return out_.host_counters(mu_, counters_); }

void PtyHost::end_of_elaboration() { require_connected(name()); }

// Active from the start: the kernel waits for the terminal rather than end by starvation.
void PtyHost::start_of_simulation() { attached_ = inbox_.async_attach_suspending(); }

void PtyHost::run() {
    const sc_core::sc_time controller_receive = cfg_.format.receive_time();
    for (;;) {
        std::optional<Item> item = pop_front_locked(mu_, in_);
        if (!item) {
            wait(inbox_.arrived);
            continue;
        }
        if (item->kind == Item::all_closed) {
            if (!cfg_.end_on_disconnect) continue;
            // Every byte the client wrote is on the line: the session is over.
            ended_ = true;
            if (attached_) inbox_.async_detach_suspending();
            attached_ = false;
            sc_core::sc_pause();
            return;
        }
        const SerialFormat& f = item->format;
        const sc_core::sc_time space = nul_space(f);
        if (item->value == 0 && space > controller_receive) {
            // The SPACE outlasts a character of the controller's: on a real wire this is a BREAK,
            // and the 82510 detects it as one.
            line_->insert_break(side_, space);
            std::lock_guard<std::mutex> lock(mu_);
            ++counters_.breaks_sent;
        } else {
            // One character per frame time of the client's format: the pace of a real terminal.
            line_->transmit(side_, SerialWord::encode(item->value, f));
            std::lock_guard<std::mutex> lock(mu_);
            ++counters_.bytes_sent;
        }
        wait(f.frame_time());
    }
}

void PtyHost::rx_char(const SerialRx& c) {
    out_.push(c);
    asio::post(io_, [this] { start_write(); }); // thread-safe; never blocks
}

void PtyHost::rx_break(bool active) { out_.note_break(active); }

// ---------------------------------------------------------------------------------------------
// io thread

void PtyHost::start_read() {
    master_.async_read_some(asio::buffer(rbuf_), [this](const boost::system::error_code& ec, std::size_t n) {
        // While the host holds the slave open a read fails only when the pty is being closed.
        if (stopping_ || ec) return;
        // The client set its termios before it wrote: read them now, as close to the write as
        // the host can see it.
        termios t{};
        const bool known = ::tcgetattr(slave_fd_, &t) == 0 && termios_baud(::cfgetospeed(&t)) != 0;
        const SerialFormat f = client_format();
        {
            std::lock_guard<std::mutex> lock(mu_);
            for (std::size_t i = 0; i < n; ++i) in_.push_back({Item::byte, rbuf_[i], f});
            counters_.bytes_in += n;
            if (!known) counters_.unknown_speed += n;
        }
        inbox_.async_request_update();
        start_read();
    });
}

void PtyHost::start_watch() {
    watch_.async_read_some(asio::buffer(events_), [this](const boost::system::error_code& ec, std::size_t n) {
        if (stopping_ || ec) return;
        bool last_closed = false;
        for (std::size_t at = 0; at + sizeof(inotify_event) <= n;) {
            inotify_event ev{};
            std::memcpy(&ev, events_.data() + at, sizeof ev);
            at += sizeof ev + ev.len;
            std::lock_guard<std::mutex> lock(mu_);
            if (ev.mask & IN_OPEN) {
                ++open_count_;
                ++counters_.connections;
            }
            if ((ev.mask & IN_CLOSE) && open_count_ > 0) {
                ++counters_.disconnects;
                last_closed = --open_count_ == 0;
            }
        }
        if (last_closed) {
            settle_.expires_after(kCloseSettle);
            settle_.async_wait([this](const boost::system::error_code& e) {
                if (stopping_ || e) return;
                {
                    std::lock_guard<std::mutex> lock(mu_);
                    if (open_count_ != 0) return; // another client came meanwhile
                    in_.push_back({Item::all_closed, 0, cfg_.format});
                }
                inbox_.async_request_update();
            });
        }
        start_watch();
    });
}

void PtyHost::start_write() {
    if (writing_ || stopping_ || !out_.take(wbuf_)) return;
    writing_ = true;
    asio::async_write(master_, asio::buffer(wbuf_), [this](const boost::system::error_code& ec, std::size_t n) {
        writing_ = false;
        if (stopping_) return;
        {
            std::lock_guard<std::mutex> lock(mu_);
            counters_.bytes_out += n;
        }
        if (!ec) start_write();
    });
}

} // namespace rcsim
