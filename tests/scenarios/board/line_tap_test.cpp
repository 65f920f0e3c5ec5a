// The serial line's passive tap (SerialLine::on_deliver): an observer is handed exactly what the
// receiving endpoint gets, in the receiver's decoding, including its errors and BREAK events.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include "models/serial_line.h"

#include "models/clock.h"
#include "tests/support/sc_test.h"

#include <functional>
#include <vector>

using namespace rcsim;
using sc_core::sc_time;

namespace {

struct Recorder : SerialEndpoint {
    SerialFormat fmt;
    std::vector<SerialRx> chars;
    std::vector<bool> breaks;
    explicit Recorder(SerialFormat f) : fmt(f) {}
    SerialFormat rx_format() const override { return fmt; }
    void rx_char(const SerialRx& c) override { chars.push_back(c); }
    void rx_break(bool on) override { breaks.push_back(on); }
};

void at(const sc_time& t, std::function<void()> f) {
    test::spawn_checked([t, f] {
        sc_core::wait(t);
        f();
    });
}

} // namespace

TEST(SerialLineTap, SeesWhatTheReceiverGetsErrorsAndBreaksIncluded) {
    // 10 kbps 8E1 on both sides: a character takes 1.1 ms. From a: 0x41, then 0x42 with data
    // bit 0 flipped by a fault (a parity error at the receiver, data 0x43). From b: 0x06, then
    // a 5 ms BREAK (detected one frame after its fall, terminated at its end).
    const SerialFormat f = SerialFormat::rs232(10'000);
    SerialLine line("line");
    Recorder ea(f), eb(f);
    line.attach(SerialLine::a, ea);
    line.attach(SerialLine::b, eb);
    std::vector<SerialLine::Delivered> seen;
    std::vector<std::size_t> endpoint_had; // chars the endpoint on the far side had when tapped
    line.on_deliver = [&](const SerialLine::Delivered& d) {
        seen.push_back(d);
        endpoint_had.push_back(d.from == SerialLine::a ? eb.chars.size() : ea.chars.size());
    };
    line.inject(SerialLine::a, 1, FaultKind::flip_data_bit, 0);
    at(us(0), [&] { line.transmit(SerialLine::a, SerialWord::encode(0x41, f)); });
    at(us(2000), [&] { line.transmit(SerialLine::a, SerialWord::encode(0x42, f)); });
    at(us(4000), [&] { line.transmit(SerialLine::b, SerialWord::encode(0x06, f)); });
    at(us(6000), [&] { line.insert_break(SerialLine::b, us(5000)); });
    sc_core::sc_start();

    ASSERT_EQ(eb.chars.size(), 2u);
    ASSERT_EQ(ea.chars.size(), 1u);
    ASSERT_EQ(seen.size(), 5u);
    using D = SerialLine::Delivered;
    for (std::size_t i : {0u, 1u, 2u}) EXPECT_EQ(seen[i].kind, D::character);
    EXPECT_EQ(seen[0].from, SerialLine::a);
    EXPECT_EQ(seen[0].rx.data, eb.chars[0].data);
    EXPECT_EQ(seen[0].rx.data, 0x41);
    EXPECT_FALSE(seen[0].rx.parity_error);
    EXPECT_EQ(seen[1].rx.data, 0x43);
    EXPECT_TRUE(seen[1].rx.parity_error);
    EXPECT_EQ(seen[1].rx.parity_error, eb.chars[1].parity_error);
    EXPECT_EQ(seen[1].rx.stop, eb.chars[1].stop);
    EXPECT_EQ(seen[2].from, SerialLine::b);
    EXPECT_EQ(seen[2].rx.data, 0x06);
    EXPECT_EQ(seen[3].kind, D::break_on);
    EXPECT_EQ(seen[4].kind, D::break_off);
    EXPECT_EQ(seen[3].from, SerialLine::b);
    EXPECT_EQ(ea.breaks, (std::vector<bool>{true, false}));
    // Each tap call comes just before its endpoint gets the character.
    EXPECT_EQ(endpoint_had[0], 0u);
    EXPECT_EQ(endpoint_had[1], 1u);
    EXPECT_EQ(endpoint_had[2], 0u);
}
