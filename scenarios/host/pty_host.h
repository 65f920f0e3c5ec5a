// rcsim — a pseudo-terminal backend for a simulated serial port.
//
// `PtyHost` is the far end of one RS-232C line whose other end is the slave side of a Unix98
// pseudo-terminal (/dev/pts/N, and optionally a stable symlink to it): minicom, screen, socat or
// pyserial open it as they would open /dev/ttyS0 (docs/serial.md "A pty as the serial port").
// Same shape as TcpHost (tcp_host.h): an Asio io thread reads the pty master into a
// mutex-protected queue that reaches SystemC only through HostInbox (host_inbox.h); an SC_THREAD
// puts the bytes on the line one frame time apart; the controller's bytes are written back by the
// io thread, so the simulation never blocks on the terminal. Runs are paced to wall-clock time
// (RealtimePacer) as with a tcp host.
//
// The client's termios settings are the line format of its side, as on a real wire:
//   * baud rate and stop bits (CSTOPB) are read from the slave (tcgetattr on a slave fd the host
//     keeps open) when a byte is taken from the master, and at each START edge the controller
//     sends: a client at another baud rate than the controller's 82510 gets, and causes, exactly
//     the garbage and framing errors a mismatched wire gives (the line's sampling rule,
//     docs/serial.md);
//   * data bits and parity come from the scenario's `format:`: the Linux pty driver rewrites
//     CSIZE to CS8 and clears PARENB on every tcsetattr (drivers/tty/pty.c, pty_set_termios), so
//     a client's character size and parity cannot be seen on a pty.
//
// BREAK: a Linux pty has no break_ctl, so tcsendbreak() and TIOCSBRK on the slave succeed and
// reach the master as nothing at all (no TIOCPKT status either). What a pty does carry is the
// physical definition of a BREAK, the line at SPACE for longer than a character: a NUL sent at a
// baud rate low enough that its SPACE cells (START, the zero data bits, a zero parity bit) outlast
// the controller's receive time becomes insert_break() of that length on the line. E.g. pyserial:
// `s.baudrate = 300; s.write(b"\0")` is a 30 ms BREAK to a 9600,8E1 port.
//
// Clients come and go unseen by the pty itself (the host holds the slave open, so the master
// never sees a hangup): an inotify watch on the slave counts opens and closes. With
// end_on_disconnect the run ends once no client has it open any more and every byte it wrote is
// on the line.
#pragma once

#include "models/serial_line.h"
#include "scenarios/host/host_inbox.h"
#include "scenarios/host/host_line.h"
#include "scenarios/host/host_outbox.h"

#include <boost/asio.hpp>
#include <systemc>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace rcsim {

struct PtyHostConfig {
    /// The port's format: the slave's initial baud rate and stop bits, and the client's data bits
    /// and parity throughout (see above).
    SerialFormat format = SerialFormat::rs232(9600);
    std::string link;                  // a symlink to the slave ("" = none); removed at exit
    bool end_on_disconnect = false;    // sc_pause() when the last client closes it (duration_s: 0)
    std::size_t max_buffer = 1u << 20; // controller bytes held while the terminal does not read
};

/// The termios speed constant for `bps` (B0 when it is not one of the standard rates).
unsigned termios_speed(std::uint64_t bps);
/// The rate of a termios speed constant (0 for B0 and for an unknown constant).
std::uint64_t termios_baud(unsigned speed);

/// The SPACE a NUL in format `f` puts on the line: START, the data bits and a zero parity bit.
sc_core::sc_time nul_space(const SerialFormat& f);

class PtyHost : public sc_core::sc_module, public HostLineEnd {
public:
    struct Counters {
        std::uint64_t bytes_in = 0;       // read from the terminal
        std::uint64_t bytes_sent = 0;     // put on the line as characters
        std::uint64_t breaks_sent = 0;    // slow NULs put on the line as a BREAK
        std::uint64_t bytes_received = 0; // from the controller
        std::uint64_t bytes_out = 0;      // written to the terminal
        std::uint64_t bytes_dropped = 0;  // beyond max_buffer
        std::uint64_t line_errors = 0;    // controller bytes with a parity/framing error
        std::uint64_t breaks = 0;         // BREAKs from the controller (not forwarded)
        std::uint64_t unknown_speed = 0;  // bytes sent while the slave's speed was B0 or non-standard
        std::uint64_t connections = 0;    // opens of the slave by clients
        std::uint64_t disconnects = 0;    // closes
    };

    /// Opens the pty (raw mode, the port's baud rate and stop bits), makes the link and starts
    /// the io thread. Throws rcsim::ConfigError naming the link when it cannot be made.
    PtyHost(sc_core::sc_module_name name, const PtyHostConfig& cfg);
    ~PtyHost() override;

    /// The slave device, "/dev/pts/N".
    const std::string& slave_path() const { return slave_path_; }
    /// What a client opens: the link if there is one, else the slave.
    const std::string& path() const { return cfg_.link.empty() ? slave_path_ : cfg_.link; }
    /// The client's side of the line now: the slave's baud rate and stop bits, the port's data
    /// bits and parity (the port's baud rate while the slave's speed is B0 or non-standard).
    SerialFormat client_format() const;
    /// A consistent copy (the io thread updates some counters).
    Counters counters() const;
    /// True once the last client closed the port with end_on_disconnect set and the host paused
    /// the run.
    bool ended() const { return ended_; }

    SerialFormat rx_format() const override { return client_format(); }
    void rx_char(const SerialRx& c) override;
    void rx_break(bool active) override;

private:
    struct Item {
        enum Kind : std::uint8_t { byte, all_closed } kind;
        std::uint8_t value;
        SerialFormat format; // the client's format when the byte was read
    };
    /// How long after the last close the host takes the client's last bytes as read: a pty
    /// write reaches the master through the kernel's flip-buffer work, not at once.
    static constexpr std::chrono::milliseconds kCloseSettle{100};

    PtyHostConfig cfg_;
    HostInbox inbox_;
    bool attached_ = false;
    bool ended_ = false;
    int slave_fd_ = -1; // held open: the slave's termios persist, and reads never see EIO
    std::string slave_path_;
    bool linked_ = false;

    // Shared between the io thread and SystemC: the input under mu_, the output in the outbox.
    mutable std::mutex mu_;
    std::deque<Item> in_; // terminal -> line
    Counters counters_;   // the outbox's counters are its own
    HostOutbox out_;      // controller -> terminal

    // io thread only (after construction).
    boost::asio::io_context io_;
    boost::asio::posix::stream_descriptor master_;
    boost::asio::posix::stream_descriptor watch_; // inotify on the slave
    boost::asio::steady_timer settle_;
    std::array<char, 4096> events_{};
    unsigned open_count_ = 0;
    std::array<std::uint8_t, 1024> rbuf_{};
    std::vector<std::uint8_t> wbuf_;
    bool writing_ = false;
    std::atomic<bool> stopping_{false};
    std::thread thread_;

    void open_pty();
    void make_link();
    void start_of_simulation() override;
    void end_of_elaboration() override;
    void run();
    // io thread
    void start_read();
    void start_watch();
    void start_write();
};

} // namespace rcsim
