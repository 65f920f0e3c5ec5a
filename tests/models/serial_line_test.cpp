// Tests of the bit-timed RS-232C line: exact character times, the sampling rule for mismatched
// receivers, BREAK, and every kind of fault injection.
#include "models/serial_line.h"

#include "models/clock.h"
#include "tests/support/sc_test.h"
#include "tests/support/serial_times.h"

#include <functional>
#include <memory>
#include <sstream>

using namespace rcsim;
using sc_core::sc_time;

namespace {

struct Recorder : SerialEndpoint {
    SerialFormat fmt;
    std::vector<SerialRx> chars;
    std::vector<std::pair<sc_time, bool>> breaks;
    explicit Recorder(SerialFormat f) : fmt(f) {}
    SerialFormat rx_format() const override { return fmt; }
    void rx_char(const SerialRx& c) override { chars.push_back(c); }
    void rx_break(bool on) override { breaks.emplace_back(sc_core::sc_time_stamp(), on); }
};

/// Runs `f` at simulated time `t` (a spawned thread; call before sc_start).
void at(const sc_time& t, std::function<void()> f) {
    test::spawn_checked([t, f] {
        sc_core::wait(t);
        f();
    });
}

// The 82510 bit time: 18.432 MHz, divisor 60, 16x clock from f/2 = 1920 clocks a bit.
const BitTime k82510_9600 = BitTime::clocked(18'432'000, 32 * 60);

SerialFormat fmt(BitTime bt, unsigned data = 8, Parity p = Parity::even, unsigned stop_halves = 2) {
    SerialFormat f;
    f.bit = bt;
    f.data_bits = data;
    f.parity = p;
    f.stop_halves = stop_halves;
    return f;
}

} // namespace

TEST(SerialFormat, ElevenBitsAt9600From18432kHzIs1145833ns) {
    const SerialFormat f = fmt(k82510_9600);
    EXPECT_EQ(f.cells() + 1, 11u);
    EXPECT_EQ(f.receive_time(), ps(1'145'833'333));
    EXPECT_EQ(f.frame_time(), ps(1'145'833'333));
    EXPECT_EQ(f.receive_time().value() / 1000, 1'145'833u); // exact to the nanosecond
}

TEST(SerialFormat, StopBitsLengthenTheFrameNotTheReceiveTime) {
    const SerialFormat two = fmt(BitTime::baud(10'000), 8, Parity::none, 4);
    EXPECT_EQ(two.frame_time(), us(1100));   // 1 + 8 + 2 bits of 100 us
    EXPECT_EQ(two.receive_time(), us(1000)); // ends with the first stop bit
    const SerialFormat onehalf = fmt(BitTime::baud(10'000), 5, Parity::none, 3);
    EXPECT_EQ(onehalf.frame_time(), us(750));
}

TEST(SerialFormat, ParseAndDescribe) {
    const SerialFormat f = SerialFormat::parse("115200,7O2");
    EXPECT_EQ(f.bit, BitTime::baud(115200));
    EXPECT_EQ(f.data_bits, 7u);
    EXPECT_EQ(f.parity, Parity::odd);
    EXPECT_EQ(f.stop_halves, 4u);
    EXPECT_EQ(f.describe(), "115200,7O2");
    EXPECT_EQ(SerialFormat::parse("300,5N1.5").describe(), "300,5N1.5");
}

TEST(SerialFormat, BadValuesAreNamed) {
    auto message = [](const std::string& s) {
        try {
            SerialFormat::parse(s);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message("9600,8X1").find("'X'"), std::string::npos);
    EXPECT_NE(message("9600,4N1").find("'4'"), std::string::npos);
    EXPECT_NE(message("9600,8N3").find("'3'"), std::string::npos);
    EXPECT_NE(message("fast,8N1").find("fast"), std::string::npos);
    SerialFormat f = fmt(BitTime::baud(9600), 10);
    EXPECT_THROW(f.validate(), std::invalid_argument);
}

TEST(SerialWord, EncodesStartDataParityStop) {
    // 0x41 8E1: START 0, data 1000 0010 (LSB first), parity even of two ones = 0, STOP 1.
    const SerialWord w = SerialWord::encode(0x41, fmt(BitTime::baud(9600)));
    EXPECT_EQ(w.ncells, 11u);
    EXPECT_EQ(w.cells, (0x41u << 1) | (0u << 9) | (1u << 10));
    const SerialWord odd = SerialWord::encode(0x41, fmt(BitTime::baud(9600), 8, Parity::odd));
    EXPECT_EQ(odd.cells, (0x41u << 1) | (1u << 9) | (1u << 10));
    const SerialWord forced = SerialWord::encode(0x41, fmt(BitTime::baud(9600)), 1);
    EXPECT_EQ((forced.cells >> 9) & 1, 1);
}

TEST(SerialSampling, EveryFormatRoundTrips) {
    for (unsigned data = 5; data <= 9; ++data)
        for (Parity p : {Parity::none, Parity::odd, Parity::even, Parity::mark, Parity::space})
            for (unsigned stop = 2; stop <= 4; ++stop)
                for (unsigned v = 0; v < (1u << data); v += 7) {
                    const SerialFormat f = fmt(k82510_9600, data, p, stop);
                    SerialRx rx;
                    ASSERT_TRUE(sample_word(SerialWord::encode(static_cast<std::uint16_t>(v), f), f, rx));
                    EXPECT_EQ(rx.data, v);
                    EXPECT_FALSE(rx.parity_error);
                    EXPECT_FALSE(rx.framing_error);
                }
}

TEST(SerialSampling, HostAtNominalBaudAndUartAtDerivedClockAgree) {
    // 9600 exactly vs 18.432 MHz / 1920: identical bit time, so no error at all.
    SerialRx rx;
    ASSERT_TRUE(sample_word(SerialWord::encode(0xA5, fmt(BitTime::baud(9600))), fmt(k82510_9600), rx));
    EXPECT_EQ(rx.data, 0xA5);
    EXPECT_FALSE(rx.parity_error || rx.framing_error);
}

TEST(SerialSampling, ReceiverAtTwiceTheBaudSeesEachCellTwice) {
    // Sample k of a 9600 receiver falls in 4800 transmitter cell floor((2k+1)/4).
    const SerialFormat tx = fmt(BitTime::baud(4800), 8, Parity::none);
    const SerialFormat rx = fmt(BitTime::baud(9600), 8, Parity::none);
    SerialRx c;
    ASSERT_TRUE(sample_word(SerialWord::encode(0xFF, tx), rx, c));
    EXPECT_EQ(c.data, 0xFE); // data bit 0 lands in the START cell
    EXPECT_FALSE(c.framing_error);
    ASSERT_TRUE(sample_word(SerialWord::encode(0x00, tx), rx, c));
    EXPECT_EQ(c.data, 0x00);
    EXPECT_TRUE(c.framing_error); // the stop sample lands in data bit 3 (SPACE)
}

TEST(SerialSampling, ParityReceiverOnANoParityLineReadsTheStopBitAsParity) {
    const SerialFormat tx = fmt(BitTime::baud(9600), 8, Parity::none);
    const SerialFormat rx = fmt(BitTime::baud(9600), 8, Parity::even);
    SerialRx c;
    ASSERT_TRUE(sample_word(SerialWord::encode(0x03, tx), rx, c)); // even ones: parity should be 0
    EXPECT_TRUE(c.parity_error);
    EXPECT_FALSE(c.framing_error); // its stop sample reads the idle line
    ASSERT_TRUE(sample_word(SerialWord::encode(0x01, tx), rx, c)); // odd ones: parity 1 = the STOP
    EXPECT_FALSE(c.parity_error);
}

TEST(SerialSampling, ShortSpaceIsACharacter) {
    const SerialFormat f = fmt(BitTime::baud(10'000)); // 100 us bits
    SerialRx c;
    ASSERT_TRUE(sample_space(us(500), f, c)); // START + 4 data bits at SPACE
    EXPECT_EQ(c.data, 0xF0);
    EXPECT_TRUE(c.parity_error); // parity sample reads MARK, even parity of 0xF0 is 0
    EXPECT_FALSE(c.framing_error);
    EXPECT_FALSE(sample_space(us(40), f, c)); // gone before the START centre: a glitch
}

TEST(SerialLine, DeliversAtTheEndOfTheReceiversFirstStopBit) {
    SerialLine line("line");
    Recorder tx(fmt(k82510_9600)), rx(fmt(k82510_9600));
    line.attach(SerialLine::a, tx);
    line.attach(SerialLine::b, rx);
    at(us(10), [&] {
        line.transmit(SerialLine::a, SerialWord::encode('A', tx.fmt));
    });
    sc_core::sc_start();
    ASSERT_EQ(rx.chars.size(), 1u);
    EXPECT_EQ(rx.chars[0].data, 'A');
    EXPECT_EQ(rx.chars[0].start, us(10));
    EXPECT_EQ(rx.chars[0].stop, us(10) + rcsim::test::char_time_9600_8e1());
    EXPECT_EQ(sc_core::sc_time_stamp(), rx.chars[0].stop);
    EXPECT_TRUE(tx.chars.empty());
    EXPECT_EQ(line.stats(SerialLine::a).delivered, 1u);
}

TEST(SerialLine, BackToBackCharactersBothDirections) {
    SerialLine line("line");
    const SerialFormat f = fmt(BitTime::baud(115200), 8, Parity::none);
    Recorder ea(f), eb(f);
    line.attach(SerialLine::a, ea);
    line.attach(SerialLine::b, eb);
    test::spawn_checked([&] {
        for (char c : std::string("hello")) {
            line.transmit(SerialLine::a, SerialWord::encode(static_cast<std::uint8_t>(c), f));
            sc_core::wait(f.frame_time());
        }
    });
    test::spawn_checked([&] {
        for (char c : std::string("world")) {
            line.transmit(SerialLine::b, SerialWord::encode(static_cast<std::uint8_t>(c), f));
            sc_core::wait(f.frame_time());
        }
    }, "send_world");
    sc_core::sc_start();
    ASSERT_EQ(eb.chars.size(), 5u);
    ASSERT_EQ(ea.chars.size(), 5u);
    std::string got_b, got_a;
    for (std::size_t i = 0; i < 5; ++i) {
        got_b += static_cast<char>(eb.chars[i].data);
        got_a += static_cast<char>(ea.chars[i].data);
        EXPECT_EQ(eb.chars[i].stop, f.frame_time() * static_cast<double>(i + 1));
    }
    EXPECT_EQ(got_b, "hello");
    EXPECT_EQ(got_a, "world");
}

TEST(SerialLine, ReceiverFormatIsTakenAtTheStartEdge) {
    SerialLine line("line");
    Recorder tx(fmt(BitTime::baud(9600))), rx(fmt(BitTime::baud(4800)));
    line.attach(SerialLine::a, tx);
    line.attach(SerialLine::b, rx);
    at(sc_core::SC_ZERO_TIME, [&] { line.transmit(SerialLine::a, SerialWord::encode(0xAA, tx.fmt)); });
    at(us(100), [&] { rx.fmt = tx.fmt; }); // too late for the character in flight
    sc_core::sc_start();
    ASSERT_EQ(rx.chars.size(), 1u);
    EXPECT_EQ(rx.chars[0].stop, fmt(BitTime::baud(4800)).receive_time());
    // 4800 samples fall in 9600 cells 3, 5, 7, 9 (d2, d4, d6, parity: all SPACE), then idle.
    EXPECT_EQ(rx.chars[0].data, 0xF0);
}

TEST(SerialLine, BreakDetectAfterOneReceiverFrameAndTerminate) {
    SerialLine line("line");
    const SerialFormat f = fmt(BitTime::baud(10'000)); // 1100 us a character
    Recorder ea(f), eb(f);
    line.attach(SerialLine::a, ea);
    line.attach(SerialLine::b, eb);
    at(us(50), [&] { line.set_break(SerialLine::a, true); });
    at(us(5000), [&] { line.set_break(SerialLine::a, false); });
    sc_core::sc_start();
    ASSERT_EQ(eb.breaks.size(), 2u);
    EXPECT_EQ(eb.breaks[0], std::make_pair(us(1150), true));
    EXPECT_EQ(eb.breaks[1], std::make_pair(us(5000), false));
    EXPECT_TRUE(eb.chars.empty());
    EXPECT_EQ(line.stats(SerialLine::a).breaks, 1u);
}

TEST(SerialLine, BreakShorterThanAFrameArrivesAsACharacter) {
    SerialLine line("line");
    const SerialFormat f = fmt(BitTime::baud(10'000));
    Recorder ea(f), eb(f);
    line.attach(SerialLine::a, ea);
    line.attach(SerialLine::b, eb);
    at(us(0), [&] { line.insert_break(SerialLine::a, us(1000)); }); // 10 bits: START..parity
    sc_core::sc_start();
    EXPECT_TRUE(eb.breaks.empty());
    ASSERT_EQ(eb.chars.size(), 1u);
    EXPECT_EQ(eb.chars[0].data, 0);
    EXPECT_FALSE(eb.chars[0].framing_error);
    EXPECT_EQ(eb.chars[0].stop, us(1100));
}

TEST(SerialLineFaults, FlippedDataBitIsAParityError) {
    SerialLine line("line");
    const SerialFormat f = fmt(BitTime::baud(9600));
    Recorder ea(f), eb(f);
    line.attach(SerialLine::a, ea);
    line.attach(SerialLine::b, eb);
    line.inject(SerialLine::a, 1, FaultKind::flip_data_bit, 3);
    test::spawn_checked([&] {
        for (int i = 0; i < 3; ++i) {
            line.transmit(SerialLine::a, SerialWord::encode(0x30, f));
            sc_core::wait(f.frame_time());
        }
    }, "sender");
    sc_core::sc_start();
    ASSERT_EQ(eb.chars.size(), 3u);
    EXPECT_FALSE(eb.chars[0].parity_error);
    EXPECT_EQ(eb.chars[1].data, 0x38);
    EXPECT_TRUE(eb.chars[1].parity_error);
    EXPECT_FALSE(eb.chars[2].parity_error);
    EXPECT_EQ(line.stats(SerialLine::a).faults, 1u);
}

TEST(SerialLineFaults, DropCorruptStopAndInsertedBreak) {
    SerialLine line("line");
    const SerialFormat f = fmt(BitTime::baud(9600));
    Recorder ea(f), eb(f);
    line.attach(SerialLine::a, ea);
    line.attach(SerialLine::b, eb);
    line.inject(SerialLine::a, 0, FaultKind::drop);
    line.inject(SerialLine::a, 1, FaultKind::corrupt_stop);
    test::spawn_checked([&] {
        for (std::uint8_t c : {'x', 'y', 'z'}) {
            line.transmit(SerialLine::a, SerialWord::encode(c, f));
            sc_core::wait(f.frame_time());
        }
        line.insert_break(SerialLine::a, f.frame_time() * 3.0);
    }, "sender");
    sc_core::sc_start();
    ASSERT_EQ(eb.chars.size(), 2u);
    EXPECT_EQ(eb.chars[0].data, 'y');
    EXPECT_TRUE(eb.chars[0].framing_error);
    EXPECT_EQ(eb.chars[1].data, 'z');
    EXPECT_FALSE(eb.chars[1].framing_error);
    ASSERT_EQ(eb.breaks.size(), 2u);
    EXPECT_TRUE(eb.breaks[0].second);
    EXPECT_FALSE(eb.breaks[1].second);
    EXPECT_EQ(eb.breaks[1].first - eb.breaks[0].first, f.frame_time() * 3.0 - f.receive_time());
    EXPECT_EQ(line.stats(SerialLine::a).dropped, 1u);
}

TEST(SerialLineFaults, BadInjectionsAreRejected) {
    SerialLine line("line");
    EXPECT_THROW(line.inject(SerialLine::a, 0, FaultKind::flip_data_bit, 9), std::invalid_argument);
    EXPECT_THROW(line.inject(SerialLine::a, 0, FaultKind::flip_cell, 12), std::invalid_argument);
    EXPECT_THROW(line.set_noise(1.5, 1), std::invalid_argument);
    EXPECT_THROW(line.set_noise(-0.1, 1), std::invalid_argument);
    Recorder e(fmt(BitTime::baud(9600)));
    line.attach(SerialLine::a, e);
    EXPECT_THROW(line.attach(SerialLine::a, e), std::invalid_argument);
}

namespace {
/// A line carrying `n` characters a -> b with noise `rate` from `seed`.
struct NoisyRun {
    SerialFormat f = fmt(BitTime::baud(9600));
    SerialLine line;
    Recorder ea{f}, eb{f};
    NoisyRun(const char* name, double rate, std::uint64_t seed, std::size_t n) : line(name) {
        line.attach(SerialLine::a, ea);
        line.attach(SerialLine::b, eb);
        line.set_noise(rate, seed);
        test::spawn_checked([this, n] {
            for (std::size_t i = 0; i < n; ++i) {
                line.transmit(SerialLine::a, SerialWord::encode(static_cast<std::uint16_t>(i & 0xFF), f));
                sc_core::wait(f.frame_time());
            }
        });
    }
    std::string received() const {
        std::ostringstream os;
        for (const auto& c : eb.chars)
            os << c.data << (c.parity_error ? "P" : "") << (c.framing_error ? "F" : "") << ' ';
        return os.str();
    }
};
} // namespace

TEST(SerialLineFaults, NoiseIsSeededAndAtTheRequestedRate) {
    NoisyRun r1("l1", 0.01, 42, 2000), r2("l2", 0.01, 42, 2000), r3("l3", 0.01, 43, 2000);
    sc_core::sc_start();
    const auto& s1 = r1.line.stats(SerialLine::a);
    EXPECT_GT(s1.noise_flips, 2000 * 11 * 0.01 * 0.7);
    EXPECT_LT(s1.noise_flips, 2000 * 11 * 0.01 * 1.3);
    EXPECT_NE(r1.received().find('P'), std::string::npos);
    EXPECT_EQ(s1.delivered + s1.glitches, 2000u);
    EXPECT_EQ(r1.received(), r2.received()); // same seed, same flips
    EXPECT_NE(r1.received(), r3.received());
}

TEST(SerialLineFaults, NoiseRateOneFlipsEveryCell) {
    NoisyRun r("l", 1.0, 7, 10);
    sc_core::sc_start();
    const auto& s = r.line.stats(SerialLine::a);
    EXPECT_EQ(s.noise_flips, 110u);
    EXPECT_EQ(s.glitches, 10u); // every START reads MARK
    EXPECT_EQ(s.delivered, 0u);
}

TEST(SerialLine, TraceShowsEveryCell) {
    SerialLine line("line");
    const SerialFormat f = fmt(BitTime::baud(9600));
    Recorder ea(f), eb(f);
    line.attach(SerialLine::a, ea);
    line.attach(SerialLine::b, eb);
    std::ostringstream os;
    line.trace_to(&os);
    std::vector<SerialLine::Traced> seen;
    line.on_transmit = [&](const SerialLine::Traced& t) { seen.push_back(t); };
    at(us(5), [&] { line.transmit(SerialLine::a, SerialWord::encode(0x41, f)); });
    at(us(2000), [&] { line.insert_break(SerialLine::b, us(3000)); });
    sc_core::sc_start();
    // 0x41 8E1: START 0, data 10000010, parity 0, STOP 1.
    EXPECT_NE(os.str().find("5 us a>b 01000001001 @9600bps"), std::string::npos) << os.str();
    EXPECT_NE(os.str().find("2 ms b>a BREAK on"), std::string::npos) << os.str();
    EXPECT_NE(os.str().find("5 ms b>a BREAK off"), std::string::npos) << os.str();
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_EQ(seen[0].start, us(5));
    EXPECT_FALSE(seen[0].dropped);
}

// ---- BREAK against characters ------------------------------------------------------------
// A BREAK from a side holds that side's wire at SPACE: a receiver sample taken while it is held
// reads 0, a START edge while it is held is no edge. Format 10 kbps 8E1: cells of 100 us, START
// [0,100), data bit n [100(n+1), 100(n+2)), parity [900,1000), STOP [1000,1100) us after the
// edge; the receiver samples their centres (50, 150, ..., 950, 1050 us) and has the character at
// 1100 us. Each case runs once in each direction (from a to b, and from b to a).

namespace {
/// A 10 kbps 8E1 line with characters and BREAKs sent from `from` at given times.
struct BreakRun {
    SerialFormat f = fmt(BitTime::baud(10'000));
    SerialLine line;
    Recorder ea{f}, eb{f};
    SerialLine::Side from;
    BreakRun(const char* name, SerialLine::Side s) : line(name), from(s) {
        line.attach(SerialLine::a, ea);
        line.attach(SerialLine::b, eb);
    }
    Recorder& receiver() { return from == SerialLine::a ? eb : ea; }
    Recorder& sender() { return from == SerialLine::a ? ea : eb; }
    void send_at(const sc_time& t, std::uint8_t byte) {
        at(t, [this, byte] { line.transmit(from, SerialWord::encode(byte, f)); });
    }
    void break_at(const sc_time& t, const sc_time& duration) {
        at(t, [this, duration] { line.insert_break(from, duration); });
    }
};

std::vector<std::unique_ptr<BreakRun>> both_directions() {
    std::vector<std::unique_ptr<BreakRun>> runs;
    runs.push_back(std::make_unique<BreakRun>("a_to_b", SerialLine::a));
    runs.push_back(std::make_unique<BreakRun>("b_to_a", SerialLine::b));
    return runs;
}
} // namespace

TEST(SerialLineBreak, EndingBeforeAStartBitLeavesTheCharacterIntact) {
    // BREAK [0, 1500) us: detected one frame after its fall (1100 us), ended at 1500 us. The
    // 0xA5 sent at 1600 us starts from MARK, none of its samples falls in the BREAK: intact at
    // 1600 + 1100 us.
    auto runs = both_directions();
    for (auto& r : runs) {
        r->break_at(us(0), us(1500));
        r->send_at(us(1600), 0xA5);
    }
    sc_core::sc_start();
    for (auto& r : runs) {
        SCOPED_TRACE(r->line.name());
        const Recorder& rx = r->receiver();
        ASSERT_EQ(rx.breaks.size(), 2u);
        EXPECT_EQ(rx.breaks[0], std::make_pair(us(1100), true));
        EXPECT_EQ(rx.breaks[1], std::make_pair(us(1500), false));
        ASSERT_EQ(rx.chars.size(), 1u);
        EXPECT_EQ(rx.chars[0].data, 0xA5);
        EXPECT_FALSE(rx.chars[0].parity_error || rx.chars[0].framing_error);
        EXPECT_EQ(rx.chars[0].stop, us(2700));
        EXPECT_EQ(r->line.stats(r->from).cut, 0u);
    }
}

TEST(SerialLineBreak, StartingMidCharacterZeroesTheRemainingBits) {
    // 0xFF at 0 (START 0, data 11111111, even parity 0, STOP 1), BREAK from 420 us to 5000 us.
    // Samples at 450 us and later read SPACE: data bits 3..7, parity, STOP. Received: data
    // 0b00000111 = 0x07; its even parity bit would be 1 (three ones), read 0: parity error;
    // STOP read 0: framing error. The BREAK is detected one frame after its fall (1520 us).
    auto runs = both_directions();
    for (auto& r : runs) {
        r->send_at(us(0), 0xFF);
        r->break_at(us(420), us(4580));
    }
    sc_core::sc_start();
    for (auto& r : runs) {
        SCOPED_TRACE(r->line.name());
        const Recorder& rx = r->receiver();
        ASSERT_EQ(rx.chars.size(), 1u);
        EXPECT_EQ(rx.chars[0].data, 0x07);
        EXPECT_TRUE(rx.chars[0].parity_error);
        EXPECT_TRUE(rx.chars[0].framing_error);
        EXPECT_EQ(rx.chars[0].stop, us(1100));
        ASSERT_EQ(rx.breaks.size(), 2u);
        EXPECT_EQ(rx.breaks[0], std::make_pair(us(1520), true));
        EXPECT_EQ(rx.breaks[1], std::make_pair(us(5000), false));
        EXPECT_EQ(r->line.stats(r->from).cut, 1u);
    }
}

TEST(SerialLineBreak, StartingAfterTheStopSampleLeavesTheCharacterIntact) {
    // The STOP bit is sampled at 1050 us. A BREAK falling 1 ps later: every sample read the
    // character, 0xFF arrives intact at 1100 us; the BREAK's fall is a START edge to the now idle
    // receiver and is detected one frame later. A BREAK falling at 1050 us exactly: the STOP
    // sample reads SPACE, a framing error (data and parity were read before: 0xFF, parity good).
    auto runs = both_directions();
    const sc_time after = us(1050) + ps(1);
    for (auto& r : runs) {
        r->send_at(us(0), 0xFF);
        r->break_at(after, us(3000));
    }
    BreakRun on_sample("on_stop_sample", SerialLine::a);
    on_sample.send_at(us(0), 0xFF);
    on_sample.break_at(us(1050), us(3000));
    sc_core::sc_start();
    for (auto& r : runs) {
        SCOPED_TRACE(r->line.name());
        const Recorder& rx = r->receiver();
        ASSERT_EQ(rx.chars.size(), 1u);
        EXPECT_EQ(rx.chars[0].data, 0xFF);
        EXPECT_FALSE(rx.chars[0].parity_error || rx.chars[0].framing_error);
        ASSERT_EQ(rx.breaks.size(), 2u);
        EXPECT_EQ(rx.breaks[0], std::make_pair(after + us(1100), true));
    }
    ASSERT_EQ(on_sample.eb.chars.size(), 1u);
    EXPECT_EQ(on_sample.eb.chars[0].data, 0xFF);
    EXPECT_FALSE(on_sample.eb.chars[0].parity_error);
    EXPECT_TRUE(on_sample.eb.chars[0].framing_error);
}

TEST(SerialLineBreak, CoveringAWholeCharacterSwallowsIt) {
    // BREAK [0, 5000) us; 0x5A sent at 1000 us: its START finds the wire already at SPACE, so
    // there is no edge and no character of its own. The receiver sees one all-zero character
    // with its STOP at SPACE, i.e. the BREAK: detected at 1100 us, ended at 5000 us.
    auto runs = both_directions();
    for (auto& r : runs) {
        r->break_at(us(0), us(5000));
        r->send_at(us(1000), 0x5A);
    }
    sc_core::sc_start();
    for (auto& r : runs) {
        SCOPED_TRACE(r->line.name());
        const Recorder& rx = r->receiver();
        EXPECT_TRUE(rx.chars.empty());
        ASSERT_EQ(rx.breaks.size(), 2u);
        EXPECT_EQ(rx.breaks[0], std::make_pair(us(1100), true));
        EXPECT_EQ(rx.breaks[1], std::make_pair(us(5000), false));
        EXPECT_EQ(r->line.stats(r->from).chars, 1u);
        EXPECT_EQ(r->line.stats(r->from).swallowed, 1u);
        EXPECT_EQ(r->line.stats(r->from).delivered, 0u);
    }
}

TEST(SerialLineBreak, ShortBreakReadsTheCharacterUnderIt) {
    // BREAK [0, 300) us, 0x00 sent at 200 us (inside it: swallowed). The receiver starts on the
    // BREAK's fall at 0 and samples the wire: SPACE until 300 us, then the 0x00's cells (offset
    // from 200 us): samples 350..850 us read its data cells 1..6 (0), parity at 950 its data
    // bit 6 (0), STOP at 1050 its data bit 7 (0). Received: 0x00, parity good, framing error.
    auto runs = both_directions();
    for (auto& r : runs) {
        r->break_at(us(0), us(300));
        r->send_at(us(200), 0x00);
    }
    sc_core::sc_start();
    for (auto& r : runs) {
        SCOPED_TRACE(r->line.name());
        const Recorder& rx = r->receiver();
        EXPECT_TRUE(rx.breaks.empty());
        ASSERT_EQ(rx.chars.size(), 1u);
        EXPECT_EQ(rx.chars[0].data, 0x00);
        EXPECT_FALSE(rx.chars[0].parity_error);
        EXPECT_TRUE(rx.chars[0].framing_error);
        EXPECT_EQ(rx.chars[0].stop, us(1100));
        EXPECT_EQ(r->line.stats(r->from).swallowed, 1u);
    }
}

TEST(SerialLineBreak, ShortBreakInsideACharacterIsNoCharacterOfItsOwn) {
    // 0xFF at 0, BREAK [420, 700) us. Its fall comes while the receiver is inside the 0xFF, so it
    // is no START edge. Samples at 450, 550, 650 us (data bits 3, 4, 5) read SPACE; the others
    // read the character: data 0b11000111 = 0xC7 (five ones: even parity 1, read 0 at 950 us:
    // parity error), STOP good. Nothing else arrives.
    auto runs = both_directions();
    for (auto& r : runs) {
        r->send_at(us(0), 0xFF);
        r->break_at(us(420), us(280));
    }
    sc_core::sc_start();
    for (auto& r : runs) {
        SCOPED_TRACE(r->line.name());
        const Recorder& rx = r->receiver();
        EXPECT_TRUE(rx.breaks.empty());
        ASSERT_EQ(rx.chars.size(), 1u);
        EXPECT_EQ(rx.chars[0].data, 0xC7);
        EXPECT_TRUE(rx.chars[0].parity_error);
        EXPECT_FALSE(rx.chars[0].framing_error);
    }
}

TEST(SerialLineBreak, StartAtTheReleaseIsAnEdgeAndAtTheFallIsNotWhateverTheCallOrder) {
    // A START sent at the instant a BREAK is released rises out of it: received intact. One sent
    // at the instant a BREAK falls falls with it: swallowed, the BREAK is detected. Both hold for
    // either order of the two calls at that instant.
    const SerialFormat f = fmt(BitTime::baud(10'000));
    const SerialWord w = SerialWord::encode(0x3C, f);
    BreakRun rel1("release_then_send", SerialLine::a), rel2("send_then_release", SerialLine::a);
    BreakRun fall1("fall_then_send", SerialLine::a), fall2("send_then_fall", SerialLine::a);
    at(us(0), [&] {
        rel1.line.set_break(SerialLine::a, true);
        rel2.line.set_break(SerialLine::a, true);
        fall1.line.set_break(SerialLine::a, true);
        fall1.line.transmit(SerialLine::a, w);
        fall2.line.transmit(SerialLine::a, w);
        fall2.line.set_break(SerialLine::a, true);
    });
    at(us(2000), [&] {
        rel1.line.set_break(SerialLine::a, false);
        rel1.line.transmit(SerialLine::a, w);
        rel2.line.transmit(SerialLine::a, w);
        rel2.line.set_break(SerialLine::a, false);
        fall1.line.set_break(SerialLine::a, false);
        fall2.line.set_break(SerialLine::a, false);
    });
    sc_core::sc_start();
    for (BreakRun* r : {&rel1, &rel2}) {
        SCOPED_TRACE(r->line.name());
        ASSERT_EQ(r->eb.chars.size(), 1u);
        EXPECT_EQ(r->eb.chars[0].data, 0x3C);
        EXPECT_FALSE(r->eb.chars[0].parity_error || r->eb.chars[0].framing_error);
        EXPECT_EQ(r->eb.chars[0].stop, us(3100));
        EXPECT_EQ(r->line.stats(SerialLine::a).swallowed, 0u);
    }
    for (BreakRun* r : {&fall1, &fall2}) {
        SCOPED_TRACE(r->line.name());
        EXPECT_TRUE(r->eb.chars.empty());
        ASSERT_EQ(r->eb.breaks.size(), 2u);
        EXPECT_EQ(r->eb.breaks[0], std::make_pair(us(1100), true));
        EXPECT_EQ(r->line.stats(SerialLine::a).swallowed, 1u);
    }
}

TEST(SerialLineBreak, ABreakLeavesTheOtherDirectionAlone) {
    // Separate wires: a BREAK from a holds a->b only; 0x96 from b during it arrives intact.
    BreakRun r("other_direction", SerialLine::a);
    r.break_at(us(0), us(5000));
    at(us(1000), [&] { r.line.transmit(SerialLine::b, SerialWord::encode(0x96, r.f)); });
    sc_core::sc_start();
    ASSERT_EQ(r.ea.chars.size(), 1u);
    EXPECT_EQ(r.ea.chars[0].data, 0x96);
    EXPECT_FALSE(r.ea.chars[0].parity_error || r.ea.chars[0].framing_error);
    EXPECT_EQ(r.ea.chars[0].stop, us(2100));
    EXPECT_EQ(r.eb.breaks.size(), 2u);
    EXPECT_TRUE(r.ea.breaks.empty());
}
