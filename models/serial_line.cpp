// rcsim — a bit-timed RS-232C line between two serial endpoints (see serial_line.h).
#include "models/serial_line.h"

#include "models/clock.h"

#include <cctype>
#include <iterator>
#include <numeric>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace rcsim {

namespace {
constexpr std::uint64_t ps_per_s = 1'000'000'000'000ULL;

/// The level (1 = MARK) of cell `i` of `w`; past the first STOP bit the line idles at MARK.
bool cell_level(const SerialWord& w, std::uint64_t i) { return i >= w.ncells || ((w.cells >> i) & 1); }

/// Fills `out` from per-cell levels sampled by `level(k)` under receiver format `rx`.
template <typename Level>
bool sample_cells(const SerialFormat& rx, Level level, SerialRx& out) {
    if (level(0)) return false; // START not at SPACE at its centre: a glitch
    out.data = 0;
    for (unsigned k = 0; k < rx.data_bits; ++k)
        if (level(1 + k)) out.data |= static_cast<std::uint16_t>(1u << k);
    unsigned next = 1 + rx.data_bits;
    out.parity = false;
    out.parity_error = false;
    if (rx.parity != Parity::none) {
        out.parity = level(next++);
        out.parity_error = out.parity != parity_bit(out.data, rx.data_bits, rx.parity);
    }
    out.framing_error = !level(next);
    return true;
}

/// Which transmitter cell of `w` receiver sample k falls in. Sample k is (2k+1)/2 receiver bits
/// = (2k+1) rx.num / (2 rx.den) s after the START edge; that is in transmitter cell
/// floor(time / (tx.num / tx.den)), computed exactly.
class CellUnderSample {
public:
    CellUnderSample(const SerialWord& w, const SerialFormat& rx) {
        const std::uint64_t g1 = std::gcd(rx.bit.num, w.bit.num), g2 = std::gcd(rx.bit.den, w.bit.den);
        mul_ = (rx.bit.num / g1) * (w.bit.den / g2);
        div_ = 2 * (rx.bit.den / g2) * (w.bit.num / g1);
    }
    std::uint64_t operator()(unsigned k) const { return (2 * k + 1) * mul_ / div_; }

private:
    std::uint64_t mul_ = 1, div_ = 1;
};
} // namespace

// ---------------------------------------------------------------------------------------------
// Formats

const char* to_string(Parity p) {
    switch (p) {
    case Parity::none: return "none";
    case Parity::odd: return "odd";
    case Parity::even: return "even";
    case Parity::mark: return "mark";
    case Parity::space: return "space";
    }
    return "?";
}

Parity parse_parity(const std::string& s) {
    std::string l;
    for (char c : s) l += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (l == "none" || l == "n") return Parity::none;
    if (l == "odd" || l == "o") return Parity::odd;
    if (l == "even" || l == "e") return Parity::even;
    if (l == "mark" || l == "m") return Parity::mark;
    if (l == "space" || l == "s") return Parity::space;
    throw std::invalid_argument("unknown parity '" + s + "' (none, odd, even, mark, space)");
}

sc_core::sc_time ratio_time(std::uint64_t n, std::uint64_t d) {
    if (d == 0) throw std::invalid_argument("ratio_time: zero denominator");
    // n/d = whole + rem/d; rem < d, so rem * (ps_per_s % d) stays below d^2.
    const std::uint64_t whole = n / d, rem = n % d;
    const std::uint64_t frac = rem * (ps_per_s / d) + (rem * (ps_per_s % d) + d / 2) / d;
    return ps(whole * ps_per_s + frac);
}

sc_core::sc_time BitTime::span(std::uint64_t halves) const { return ratio_time(halves * num, 2 * den); }

bool parity_bit(std::uint16_t data, unsigned data_bits, Parity p) {
    unsigned v = data & ((1u << data_bits) - 1);
    bool odd_ones = false;
    for (; v; v &= v - 1) odd_ones = !odd_ones;
    switch (p) {
    case Parity::none: return false;
    case Parity::odd: return !odd_ones; // the total count of ones is odd
    case Parity::even: return odd_ones; // the total count of ones is even
    case Parity::mark: return true;
    case Parity::space: return false;
    }
    return false;
}

SerialFormat SerialFormat::rs232(std::uint64_t bps, unsigned data, Parity p, unsigned stop_bits) {
    SerialFormat f;
    f.bit = BitTime::baud(bps);
    f.data_bits = data;
    f.parity = p;
    f.stop_halves = 2 * stop_bits;
    f.validate();
    return f;
}

SerialFormat SerialFormat::parse(const std::string& s) {
    // "<baud>,<data><parity><stop>", e.g. "9600,8E1", "115200,8N1", "300,5N1.5"
    const auto comma = s.find(',');
    const std::string err = "bad serial format '" + s + "' (expected e.g. 9600,8E1)";
    if (comma == std::string::npos || comma == 0 || s.size() < comma + 4) throw std::invalid_argument(err);
    std::uint64_t bps = 0;
    for (std::size_t i = 0; i < comma; ++i) {
        if (!std::isdigit(static_cast<unsigned char>(s[i])) || bps > 100'000'000) throw std::invalid_argument(err);
        bps = bps * 10 + static_cast<std::uint64_t>(s[i] - '0');
    }
    SerialFormat f;
    f.bit = BitTime::baud(bps);
    const char d = s[comma + 1];
    if (d < '5' || d > '9') throw std::invalid_argument(err + ": data bits '" + std::string(1, d) + "'");
    f.data_bits = static_cast<unsigned>(d - '0');
    f.parity = parse_parity(std::string(1, s[comma + 2]));
    const std::string stop = s.substr(comma + 3);
    if (stop == "1") f.stop_halves = 2;
    else if (stop == "1.5") f.stop_halves = 3;
    else if (stop == "2") f.stop_halves = 4;
    else throw std::invalid_argument(err + ": stop bits '" + stop + "'");
    f.validate();
    return f;
}

void SerialFormat::validate() const {
    if (bit.num == 0 || bit.den == 0)
        throw std::invalid_argument("serial format: zero bit time (" + std::to_string(bit.num) + "/" +
                                    std::to_string(bit.den) + " s)");
    if (bit.num >= (1ULL << 32) || bit.den >= (1ULL << 32))
        throw std::invalid_argument("serial format: bit time " + std::to_string(bit.num) + "/" +
                                    std::to_string(bit.den) + " s out of range");
    if (data_bits < 5 || data_bits > 9)
        throw std::invalid_argument("serial format: data bits " + std::to_string(data_bits) + " (5..9)");
    if (stop_halves < 2 || stop_halves > 4)
        throw std::invalid_argument("serial format: stop bits " + std::to_string(stop_halves / 2.0) +
                                    " (1, 1.5 or 2)");
}

std::string SerialFormat::describe() const {
    std::ostringstream os;
    if (bit.den % bit.num == 0) os << bit.den / bit.num;
    else os << bit.bps();
    const char letters[] = {'N', 'O', 'E', 'M', 'S'};
    os << ',' << data_bits << letters[static_cast<int>(parity)];
    if (stop_halves == 3) os << "1.5";
    else os << stop_halves / 2;
    return os.str();
}

SerialWord SerialWord::encode(std::uint16_t data, const SerialFormat& f, int parity_override) {
    SerialWord w;
    w.bit = f.bit;
    w.frame = f.frame_time();
    const std::uint16_t mask = static_cast<std::uint16_t>((1u << f.data_bits) - 1);
    unsigned n = 0;
    // cell 0: START = SPACE (0)
    ++n;
    w.cells = static_cast<std::uint16_t>((data & mask) << n);
    n += f.data_bits;
    if (f.parity != Parity::none) {
        const bool p = parity_override >= 0 ? parity_override != 0 : parity_bit(data, f.data_bits, f.parity);
        w.cells |= static_cast<std::uint16_t>(p << n);
        ++n;
    }
    w.cells |= static_cast<std::uint16_t>(1u << n); // first STOP = MARK
    w.ncells = static_cast<std::uint8_t>(n + 1);
    return w;
}

// ---------------------------------------------------------------------------------------------
// Sampling

bool sample_word(const SerialWord& w, const SerialFormat& rx, SerialRx& out) {
    const CellUnderSample cell(w, rx);
    return sample_cells(rx, [&](unsigned k) { return cell_level(w, cell(k)); }, out);
}

bool sample_levels(const SerialFormat& rx, const std::function<bool(const sc_core::sc_time&)>& level,
                   SerialRx& out) {
    return sample_cells(rx, [&](unsigned k) { return level(rx.bit.span(2 * k + 1)); }, out);
}

bool sample_space(const sc_core::sc_time& space, const SerialFormat& rx, SerialRx& out) {
    return sample_levels(rx, [&](const sc_core::sc_time& t) { return t >= space; }, out);
}

// ---------------------------------------------------------------------------------------------
// The line

SerialLine::SerialLine(sc_core::sc_module_name name) : sc_module(name) {
    SC_HAS_PROCESS(SerialLine);
    SC_METHOD(deliver_a_to_b);
    sensitive << dir_[a].wake;
    dont_initialize();
    SC_METHOD(deliver_b_to_a);
    sensitive << dir_[b].wake;
    dont_initialize();
}

void SerialLine::attach(Side s, SerialEndpoint& ep) {
    if (ends_[s])
        throw std::invalid_argument(std::string(name()) + ": side " + (s == a ? "a" : "b") +
                                    " already has an endpoint");
    ends_[s] = &ep;
}

std::uint64_t SerialLine::transmit(Side from, SerialWord w) {
    Direction& d = dir_[from];
    const std::uint64_t index = d.sent++;
    ++d.stats.chars;
    bool dropped = false;
    apply_faults(from, index, w, dropped);
    if (noise_ > 0 && !dropped) {
        for (unsigned i = 0; i < w.ncells; ++i) {
            if (next_uniform() < noise_) {
                w.cells ^= static_cast<std::uint16_t>(1u << i);
                ++d.stats.noise_flips;
            }
        }
    }
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    if (on_transmit) on_transmit(Traced{from, now, w, dropped});
    if (trace_) {
        *trace_ << now << ' ' << (from == a ? "a>b" : "b>a") << ' ';
        for (unsigned i = 0; i < w.ncells; ++i) *trace_ << (((w.cells >> i) & 1) ? '1' : '0');
        *trace_ << " @" << w.bit.bps() << "bps" << (dropped ? " dropped" : "") << '\n';
    }
    if (dropped || !ends_[other(from)]) return index;
    forget_past(from);
    // The wire is already at SPACE under a BREAK: this START is no edge, the receiver never
    // starts on it (its cells can still show in a short BREAK's character, deliver_break_check).
    const bool edge = d.break_level == 0;
    d.wire.push_back(OnWire{now, w, edge});
    if (edge) schedule_char(from, d.wire.back());
    else ++d.stats.swallowed;
    return index;
}

void SerialLine::schedule_char(Side from, const OnWire& c) {
    Pending p{Pending::character, {}, c.start, c.word, ends_[other(from)]->rx_format(), 0};
    p.due = c.start + p.rx.receive_time();
    schedule(from, p);
}

void SerialLine::set_break(Side from, bool active) {
    Direction& d = dir_[from];
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    SerialEndpoint* rx = ends_[other(from)];
    if (active) {
        if (d.break_level++ > 0) return;
        ++d.break_gen;
        ++d.stats.breaks;
        d.break_detected = false;
        d.holds.push_back(Hold{now, sc_core::sc_max_time()});
        if (trace_) *trace_ << now << ' ' << (from == a ? "a>b" : "b>a") << " BREAK on\n";
        if (on_break_level) on_break_level(from, true);
        if (!rx) return;
        // A START sent at this same instant falls with the BREAK: one edge, the BREAK's (the
        // order of two calls at one time must not matter).
        for (auto it = d.queue.begin(); it != d.queue.end();) {
            if (it->kind != Pending::character || it->start != now) {
                ++it;
                continue;
            }
            it = d.queue.erase(it);
            for (OnWire& c : d.wire)
                if (c.start == now) c.edge = false;
            ++d.stats.swallowed;
        }
        Pending p{Pending::break_check, {}, now, {}, rx->rx_format(), d.break_gen};
        p.due = now + p.rx.receive_time();
        // Inside a character the fall is no START edge: that character's samples read it.
        p.edge = !receiver_busy(from, now);
        schedule(from, p);
        return;
    }
    if (d.break_level == 0 || --d.break_level > 0) return;
    d.holds.back().end = now;
    if (trace_) *trace_ << now << ' ' << (from == a ? "a>b" : "b>a") << " BREAK off\n";
    if (on_break_level) on_break_level(from, false);
    if (!rx) return;
    if (d.break_detected) {
        d.break_detected = false;
        if (on_deliver) on_deliver(Delivered{from, Delivered::break_off, {}});
        rx->rx_break(false);
    }
    // Not yet detected: the pending break_check turns the short SPACE into a character.
    // A START sent at this same instant rises out of the BREAK: it is an edge after all.
    for (OnWire& c : d.wire) {
        if (c.start != now || c.edge) continue;
        c.edge = true;
        --d.stats.swallowed;
        schedule_char(from, c);
    }
}

void SerialLine::insert_break(Side from, const sc_core::sc_time& duration) {
    set_break(from, true);
    Pending p{Pending::break_release, sc_core::sc_time_stamp() + duration, {}, {}, {}, 0};
    schedule(from, p);
}

void SerialLine::inject(Side from, std::uint64_t index, FaultKind kind, unsigned bit) {
    if (kind == FaultKind::flip_data_bit && bit > 8)
        throw std::invalid_argument(std::string(name()) + ": data bit " + std::to_string(bit) + " (0..8)");
    if (kind == FaultKind::flip_cell && bit > 11)
        throw std::invalid_argument(std::string(name()) + ": cell " + std::to_string(bit) + " (0..11)");
    if (index < dir_[from].sent)
        throw std::invalid_argument(std::string(name()) + ": character " + std::to_string(index) +
                                    " was already sent (next is " + std::to_string(dir_[from].sent) + ")");
    dir_[from].faults.emplace(index, std::make_pair(kind, bit));
}

void SerialLine::set_noise(double per_bit, std::uint64_t seed) {
    if (!(per_bit >= 0.0 && per_bit <= 1.0))
        throw std::invalid_argument(std::string(name()) + ": noise rate " + std::to_string(per_bit) + " (0..1)");
    noise_ = per_bit;
    rng_ = seed;
}

void SerialLine::apply_faults(Side from, std::uint64_t index, SerialWord& w, bool& dropped) {
    Direction& d = dir_[from];
    auto [lo, hi] = d.faults.equal_range(index);
    for (auto it = lo; it != hi; ++it) {
        const auto [kind, bit] = it->second;
        unsigned cell = 0;
        switch (kind) {
        case FaultKind::drop: dropped = true; ++d.stats.dropped; continue;
        case FaultKind::flip_data_bit: cell = 1 + bit; break;
        case FaultKind::flip_cell: cell = bit; break;
        case FaultKind::corrupt_stop: cell = w.ncells - 1u; break;
        }
        if (cell >= w.ncells) {
            SC_REPORT_ERROR(name(), ("fault on character " + std::to_string(index) + ": cell " +
                                     std::to_string(cell) + " beyond its " + std::to_string(w.ncells) + " cells")
                                        .c_str());
            continue;
        }
        if (kind == FaultKind::corrupt_stop) w.cells &= static_cast<std::uint16_t>(~(1u << cell));
        else w.cells ^= static_cast<std::uint16_t>(1u << cell);
        ++d.stats.faults;
    }
    d.faults.erase(lo, hi);
}

double SerialLine::next_uniform() {
    // splitmix64: a fixed, portable sequence per seed (std distributions are not portable).
    std::uint64_t z = (rng_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * (1.0 / 9007199254740992.0);
}

void SerialLine::schedule(Side from, Pending p) {
    Direction& d = dir_[from];
    auto it = d.queue.end();
    while (it != d.queue.begin() && std::prev(it)->due > p.due) --it;
    d.queue.insert(it, std::move(p));
    // An earlier notification overrides a later pending one, so the event tracks the head.
    d.wake.notify(d.queue.front().due - sc_core::sc_time_stamp());
}

void SerialLine::deliver(Side from) {
    Direction& d = dir_[from];
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    while (!d.queue.empty() && d.queue.front().due <= now) {
        const Pending p = std::move(d.queue.front());
        d.queue.pop_front();
        switch (p.kind) {
        case Pending::character: deliver_char(from, p); break;
        case Pending::break_check: deliver_break_check(from, p); break;
        case Pending::break_release: set_break(from, false); break;
        }
    }
    forget_past(from);
    if (!d.queue.empty()) d.wake.notify(d.queue.front().due - now);
}

void SerialLine::deliver_char(Side from, const Pending& p) {
    Direction& d = dir_[from];
    // Each sample reads the character's cell, or SPACE where a BREAK held the wire then.
    const CellUnderSample cell(p.word, p.rx);
    bool cut = false;
    const auto level = [&](unsigned k) {
        if (!cell_level(p.word, cell(k))) return false;
        if (!held(from, p.start + p.rx.bit.span(2 * k + 1))) return true;
        cut = true;
        return false;
    };
    SerialRx rx;
    if (!sample_cells(p.rx, level, rx)) {
        ++d.stats.glitches;
        return;
    }
    rx.start = p.start;
    rx.stop = p.due;
    ++d.stats.delivered;
    if (cut) ++d.stats.cut;
    if (on_deliver) on_deliver(Delivered{from, Delivered::character, rx});
    ends_[other(from)]->rx_char(rx);
}

void SerialLine::deliver_break_check(Side from, const Pending& p) {
    Direction& d = dir_[from];
    SerialEndpoint* rx = ends_[other(from)];
    if (p.gen == d.break_gen && d.break_level > 0) { // at SPACE for a whole receiver frame
        d.break_detected = true;
        if (on_deliver) on_deliver(Delivered{from, Delivered::break_on, {}});
        rx->rx_break(true);
        return;
    }
    // Released before a whole receiver frame went by. If its fall was a START edge, the receiver
    // read a character from the wire: SPACE while held, the transmitter's cells otherwise.
    if (!p.edge) return;
    SerialRx c;
    if (!sample_levels(p.rx, [&](const sc_core::sc_time& t) { return wire_level(from, p.start + t); }, c)) {
        ++d.stats.glitches;
        return;
    }
    c.start = p.start;
    c.stop = p.due;
    ++d.stats.delivered;
    if (on_deliver) on_deliver(Delivered{from, Delivered::character, c});
    rx->rx_char(c);
}

bool SerialLine::held(Side from, const sc_core::sc_time& t) const {
    for (const Hold& h : dir_[from].holds)
        if (h.start <= t && t < h.end) return true;
    return false;
}

bool SerialLine::wire_level(Side from, const sc_core::sc_time& t) const {
    if (held(from, t)) return false;
    for (const OnWire& c : dir_[from].wire) {
        if (t < c.start) continue;
        // The cell under t, past the first STOP bit MARK (as cell_level).
        for (unsigned i = 0; i < c.word.ncells; ++i)
            if (t < c.start + c.word.bit.span(2 * (i + 1u))) {
                if (!((c.word.cells >> i) & 1)) return false;
                break;
            }
    }
    return true;
}

bool SerialLine::receiver_busy(Side from, const sc_core::sc_time& t) const {
    // Between a START edge and its stop-bit sample the receiver is inside a character.
    for (const Pending& p : dir_[from].queue) {
        if (p.kind == Pending::break_release || (p.kind == Pending::break_check && !p.edge)) continue;
        if (p.start < t && t <= p.start + p.rx.bit.span(2 * p.rx.cells() + 1)) return true;
    }
    return false;
}

void SerialLine::forget_past(Side from) {
    // No pending sample is earlier than the earliest pending START (or now): older BREAKs and
    // characters can no longer be read.
    Direction& d = dir_[from];
    sc_core::sc_time horizon = sc_core::sc_time_stamp();
    for (const Pending& p : d.queue)
        if (p.kind != Pending::break_release && p.start < horizon) horizon = p.start;
    while (!d.holds.empty() && d.holds.front().end <= horizon) d.holds.pop_front();
    while (!d.wire.empty() && d.wire.front().start + d.wire.front().word.frame <= horizon) d.wire.pop_front();
}

} // namespace rcsim
