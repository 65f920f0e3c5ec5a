// rcsim — a bit-timed RS-232C line between two serial endpoints.
//
// Electrical facts modelled (EIA RS-232C as seen at the UART pins, i.e. after the line drivers):
// the line idles at MARK (1); a character is a START bit (SPACE, 0), 5..9 data bits LSB first, an
// optional parity bit (odd, even, mark or space) and 1, 1.5 or 2 STOP bits (MARK). BREAK is the
// line held at SPACE for longer than a character.
//
// Each direction is its own wire (TXD of one side to RXD of the other): its level is the
// transmitter's cells AND NOT "a BREAK from that side is held". A BREAK from side a therefore
// forces the a->b characters under it to SPACE and leaves b->a alone (rules in docs/serial.md).
//
// Cost model (events, not ticks: docs/architecture.md "Time model"): one kernel event per character and
// direction. A transmitted character carries its bit-level shape (`SerialWord`: the level of
// each bit cell and the transmitter's bit time); the line samples that shape with the
// *receiver's* bit time and format when the character is delivered, so a receiver set to another
// baud rate or format sees exactly the bits a real one would (rule in docs/serial.md):
//
//   * the receiver starts on the transmitter's START edge and samples the centre of each of its
//     own bit cells: cell k is sampled at (k + 1/2) receiver bit times after the edge;
//   * the sample reads the transmitter's cell under it; beyond the transmitter's first stop bit
//     the line is at MARK (idle);
//   * START sampled as MARK: a glitch, no character; parity checked per the receiver's format;
//     first STOP sampled as SPACE: framing error;
//   * the character is delivered when the receiver's first stop bit ends
//     (start + (1 + data + parity + 1) receiver bit times), one character per transmitted start
//     bit (the receiver resynchronises on every transmitted START edge);
//   * a sample taken while a BREAK holds the wire reads SPACE; a START edge that falls while the
//     wire is held is no edge at all, so that character is swallowed by the BREAK.
//
// Time: a bit lasts an exact fraction of a second (`BitTime`); a span of bit cells is converted
// to picoseconds with round-to-nearest in BitTime::span(), the only rounding on the serial path.
#pragma once

#include <systemc>

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <string>

namespace rcsim {

enum class Parity : std::uint8_t { none, odd, even, mark, space };
const char* to_string(Parity p);
/// "none"/"odd"/"even"/"mark"/"space" or the letter N/O/E/M/S; throws std::invalid_argument.
Parity parse_parity(const std::string& s);

/// n / d seconds as sc_time, rounded to the nearest picosecond (n, d < 2^32 keep it exact).
sc_core::sc_time ratio_time(std::uint64_t n, std::uint64_t d);

/// The length of one bit as an exact fraction of a second, num / den. A UART derives it from
/// its clock (18.432 MHz / (32 x 60) at 9600 bps: {1920, 18432000}); a host from its baud
/// rate ({1, 9600}).
struct BitTime {
    std::uint64_t num = 1;
    std::uint64_t den = 9600;

    static BitTime baud(std::uint64_t bps) { return {1, bps}; }
    static BitTime clocked(std::uint64_t hz, std::uint64_t cycles_per_bit) { return {cycles_per_bit, hz}; }

    /// `halves` half-bit cells as sc_time, rounded to the nearest picosecond.
    sc_core::sc_time span(std::uint64_t halves) const;
    double bps() const { return static_cast<double>(den) / static_cast<double>(num); }
    bool operator==(const BitTime& o) const { return num * o.den == o.num * den; }
};

/// The frame format one side transmits with, or samples with.
struct SerialFormat {
    BitTime bit;
    unsigned data_bits = 8;      // 5..9
    Parity parity = Parity::even;
    unsigned stop_halves = 2;    // 2 = 1 stop bit, 3 = 1.5, 4 = 2

    /// The project default: 9600 bps, 8 data, even parity, 1 stop (11 bits a character).
    static SerialFormat rs232(std::uint64_t bps = 9600, unsigned data = 8, Parity p = Parity::even,
                              unsigned stop_bits = 1);
    /// Parses "9600,8E1" (baud, data bits, parity letter N/O/E/M/S, stop bits 1, 1.5 or 2).
    static SerialFormat parse(const std::string& s);

    unsigned cells() const { return 1 + data_bits + (parity != Parity::none ? 1u : 0u); } // up to stop
    /// Whole character on the wire, START through the last STOP bit.
    sc_core::sc_time frame_time() const { return bit.span(2 * cells() + stop_halves); }
    /// START edge to the end of the first STOP bit: when a receiver has the character.
    sc_core::sc_time receive_time() const { return bit.span(2 * (cells() + 1)); }
    /// Throws std::invalid_argument naming the offending value.
    void validate() const;
    std::string describe() const; // "9600,8E1"
};

/// The parity bit that goes with `data` (data_bits wide) under `p` (none: 0).
bool parity_bit(std::uint16_t data, unsigned data_bits, Parity p);

/// One character as its transmitter put it on the wire.
struct SerialWord {
    std::uint16_t cells = 0;  // bit i = level of cell i (1 = MARK): START, data LSB first, parity, STOP
    std::uint8_t ncells = 0;  // cells through the first STOP bit
    BitTime bit;              // the transmitter's bit time
    sc_core::sc_time frame;   // the transmitter's whole frame (all STOP bits)

    /// Shapes `data` under `f`; `parity_override` >= 0 forces the parity cell (software parity).
    static SerialWord encode(std::uint16_t data, const SerialFormat& f, int parity_override = -1);
};

/// What a receiver made of one character.
struct SerialRx {
    std::uint16_t data = 0;      // data bits as sampled, LSB first
    bool parity = false;         // the sampled parity cell (receiver formats with parity)
    bool parity_error = false;
    bool framing_error = false;  // first STOP sampled as SPACE
    sc_core::sc_time start;      // the START edge
    sc_core::sc_time stop;       // end of the receiver's first STOP bit (= delivery time)
};

/// What a line delivers to. Both the 82510 and the simulated hosts implement it.
class SerialEndpoint {
public:
    virtual ~SerialEndpoint() = default;
    /// The format the receiver samples with; asked at the START edge of each character.
    virtual SerialFormat rx_format() const = 0;
    /// A complete character, at the end of the receiver's first STOP bit.
    virtual void rx_char(const SerialRx& c) = 0;
    /// active = true: the line has been at SPACE for one receiver frame (break detect);
    /// active = false: it went back to MARK (break terminate).
    virtual void rx_break(bool active) = 0;
};

/// Faults the line can apply to a character a side transmits.
enum class FaultKind : std::uint8_t {
    flip_data_bit,  // invert data bit `bit`: a parity error for receivers with parity
    flip_cell,      // invert raw cell `bit` (0 = START)
    drop,           // the character never arrives
    corrupt_stop,   // first STOP bit at SPACE: a framing error
};

class SerialLine : public sc_core::sc_module {
public:
    enum Side : unsigned { a = 0, b = 1 };
    static Side other(Side s) { return s == a ? b : a; }

    struct Stats {
        std::uint64_t chars = 0;        // characters transmitted from this side
        std::uint64_t delivered = 0;    // characters the far receiver got
        std::uint64_t glitches = 0;     // START sampled as MARK: nothing delivered
        std::uint64_t dropped = 0;      // removed by fault injection
        std::uint64_t faults = 0;       // characters altered by fault injection (not drops)
        std::uint64_t noise_flips = 0;  // cells inverted by random noise
        std::uint64_t breaks = 0;       // breaks started from this side
        std::uint64_t swallowed = 0;    // START edge while this side's BREAK held the wire: no character
        std::uint64_t cut = 0;          // delivered with samples a BREAK forced to SPACE
    };

    /// One transmitted character, for trace observers.
    struct Traced {
        Side from;
        sc_core::sc_time start;
        SerialWord word;
        bool dropped;
    };

    explicit SerialLine(sc_core::sc_module_name name);

    /// Attaches an endpoint to a side (once per side).
    void attach(Side s, SerialEndpoint& ep);
    bool attached(Side s) const { return ends_[s] != nullptr; }

    /// Puts `w` on the line from `from`, START edge now. The transmitter stays busy for w.frame.
    /// Returns the character's index among those sent from `from` (0-based).
    std::uint64_t transmit(Side from, SerialWord w);
    /// Holds the line at SPACE (true) or releases it (false), as a transmitter's set-break bit.
    void set_break(Side from, bool active);

    // ---- fault injection ----
    /// Applies `kind` to character number `index` sent from `from` (index as returned by
    /// transmit(); next_index() is the next one). `bit` is the data bit or cell for the flips.
    void inject(Side from, std::uint64_t index, FaultKind kind, unsigned bit = 0);
    std::uint64_t next_index(Side from) const { return dir_[from].sent; }
    /// Faults injected for characters from `from` not yet sent (an idle side keeps them all).
    std::size_t pending_faults(Side from) const { return dir_[from].faults.size(); }
    /// Holds the line from `from` at SPACE for `duration`, starting now.
    void insert_break(Side from, const sc_core::sc_time& duration);
    /// Every cell of every character in both directions is inverted with probability
    /// `per_bit` (0..1), drawn from a generator seeded with `seed` (same seed, same flips).
    void set_noise(double per_bit, std::uint64_t seed);

    /// Called for every transmitted character (e.g. a bit-level trace); empty by default.
    std::function<void(const Traced&)> on_transmit;
    /// Called when a side's BREAK starts holding its wire at SPACE (held = true) and when the
    /// wire is let go (false): with on_transmit, the wire's level at every instant (a waveform
    /// trace). Empty by default.
    std::function<void(Side from, bool held)> on_break_level;

    /// What a receiver was handed, for passive observers (a protocol analyser on the line).
    struct Delivered {
        enum Kind : std::uint8_t { character, break_on, break_off };
        Side from;   // the transmitting side; the receiver is other(from)
        Kind kind;
        SerialRx rx; // character: as the receiver decoded it (its format, its errors)
    };
    /// Called for every character and break event the far receiver gets, just before it gets it,
    /// so an observer sees exactly what the endpoint sees; empty (no cost) by default.
    std::function<void(const Delivered&)> on_deliver;
    /// Writes one line per character and break (time, side, cells) to `os` (nullptr: off).
    void trace_to(std::ostream* os) { trace_ = os; }

    const Stats& stats(Side from) const { return dir_[from].stats; }

private:
    struct Pending {
        enum Kind : std::uint8_t { character, break_check, break_release } kind;
        sc_core::sc_time due;
        sc_core::sc_time start;
        SerialWord word;
        SerialFormat rx;     // the receiver's format at the START edge
        std::uint64_t gen;   // break generation, for break_check
        bool edge = true;    // break_check: the BREAK's fall was a START edge to the receiver
    };
    /// A BREAK interval [start, end); end is sc_max_time() while it is held.
    struct Hold {
        sc_core::sc_time start, end;
    };
    /// A transmitted character kept while a BREAK character's samples may still read it.
    struct OnWire {
        sc_core::sc_time start;
        SerialWord word;
        bool edge; // its START was an edge (not swallowed): it has a Pending character
    };
    struct Direction {
        std::deque<Pending> queue; // ordered by due
        sc_core::sc_event wake;
        std::uint64_t sent = 0;
        std::multimap<std::uint64_t, std::pair<FaultKind, unsigned>> faults;
        unsigned break_level = 0;     // nested holds: transmitter bit + injected breaks
        std::uint64_t break_gen = 0;  // incremented when the line goes to SPACE
        bool break_detected = false;  // receiver was told rx_break(true) for this break
        std::deque<Hold> holds;       // BREAKs a pending sample may still fall in, oldest first
        std::deque<OnWire> wire;      // characters a pending BREAK character may still read
        Stats stats;
    };

    SerialEndpoint* ends_[2] = {nullptr, nullptr};
    Direction dir_[2];
    double noise_ = 0;
    std::uint64_t rng_ = 0;
    std::ostream* trace_ = nullptr;

    void schedule(Side from, Pending p);
    void deliver_a_to_b() { deliver(a); }
    void deliver_b_to_a() { deliver(b); }
    void deliver(Side from);
    void deliver_char(Side from, const Pending& p);
    void deliver_break_check(Side from, const Pending& p);
    void schedule_char(Side from, const OnWire& c);
    bool held(Side from, const sc_core::sc_time& t) const;
    bool wire_level(Side from, const sc_core::sc_time& t) const;
    bool receiver_busy(Side from, const sc_core::sc_time& t) const;
    void forget_past(Side from);
    void apply_faults(Side from, std::uint64_t index, SerialWord& w, bool& dropped);
    double next_uniform();
};

/// Samples `w` (START edge at offset 0) with receiver format `rx`. Exposed for tests.
/// Returns false when START reads MARK (no character).
bool sample_word(const SerialWord& w, const SerialFormat& rx, SerialRx& out);
/// Samples a SPACE of `space` length followed by MARK with receiver format `rx`.
bool sample_space(const sc_core::sc_time& space, const SerialFormat& rx, SerialRx& out);
/// Samples a character whose START edge is at offset 0 from the line level `level(t)` at each of
/// the receiver's sample times t (offsets from the edge).
bool sample_levels(const SerialFormat& rx, const std::function<bool(const sc_core::sc_time&)>& level,
                   SerialRx& out);

} // namespace rcsim
