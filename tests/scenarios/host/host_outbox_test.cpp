// Tests of the bounded outbox the tcp and pty hosts queue the controller's bytes in
// (scenarios/host/host_outbox.h): order kept, the bound never exceeded, every loss counted.
#include "scenarios/host/host_outbox.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <thread>
#include <vector>

using namespace rcsim;

namespace {

SerialRx rx(std::uint8_t byte, bool parity_error = false, bool framing_error = false) {
    SerialRx c;
    c.data = byte;
    c.parity_error = parity_error;
    c.framing_error = framing_error;
    return c;
}

} // namespace

TEST(HostOutbox, KeepsTheControllersOrderAndEmptiesOnTake) {
    HostOutbox box(8);
    std::vector<std::uint8_t> out{0xEE}; // replaced, not appended to
    EXPECT_FALSE(box.take(out));
    for (std::uint8_t b : {std::uint8_t{0x05}, std::uint8_t{'h'}, std::uint8_t{'i'}, std::uint8_t{0x06}}) box.push(rx(b));
    ASSERT_TRUE(box.take(out));
    EXPECT_EQ(out, (std::vector<std::uint8_t>{0x05, 'h', 'i', 0x06}));
    EXPECT_EQ(box.held(), 0u);
    EXPECT_FALSE(box.take(out));
    EXPECT_EQ(box.counters().received, 4u);
    EXPECT_EQ(box.counters().dropped, 0u);
}

TEST(HostOutbox, BeyondTheBoundTheOldestAreDroppedAndCounted) {
    // 10 bytes into an outbox of 4: the first 6 go, the last 4 stay in order, 6 counted as lost.
    HostOutbox box(4);
    for (std::uint8_t b = 0; b < 10; ++b) {
        box.push(rx(b));
        EXPECT_LE(box.held(), 4u) << "after byte " << int(b);
    }
    std::vector<std::uint8_t> out;
    ASSERT_TRUE(box.take(out));
    EXPECT_EQ(out, (std::vector<std::uint8_t>{6, 7, 8, 9}));
    const auto c = box.counters();
    EXPECT_EQ(c.received, 10u);
    EXPECT_EQ(c.dropped, 6u);
    EXPECT_EQ(c.received - c.dropped, out.size()); // nothing lost uncounted
}

TEST(HostOutbox, AClientThatNeverReadsHoldsNoMoreThanTheBound) {
    // A million bytes with nobody taking them: memory stays at the bound (1 KB here).
    HostOutbox box(1024);
    for (unsigned i = 0; i < 1'000'000; ++i) box.push(rx(static_cast<std::uint8_t>(i)));
    EXPECT_EQ(box.held(), 1024u);
    EXPECT_EQ(box.counters().dropped, 1'000'000u - 1024u);
    std::vector<std::uint8_t> out;
    ASSERT_TRUE(box.take(out));
    ASSERT_EQ(out.size(), 1024u);
    // The newest 1024: bytes 998976..999999, whose low bytes start at 998976 % 256 = 64.
    for (std::size_t k = 0; k < out.size(); ++k) ASSERT_EQ(out[k], static_cast<std::uint8_t>(64 + k)) << k;
}

TEST(HostOutbox, CountsLineErrorsAndBreakStartsButForwardsNoBreak) {
    HostOutbox box(16);
    box.push(rx('a', true, false));  // parity error
    box.push(rx('b', false, true));  // framing error
    box.push(rx('c', true, true));   // both: one character with errors
    box.push(rx('d'));
    box.note_break(true);
    box.note_break(false); // the end of the same BREAK
    box.note_break(true);
    const auto c = box.counters();
    EXPECT_EQ(c.line_errors, 3u);
    EXPECT_EQ(c.breaks, 2u);
    std::vector<std::uint8_t> out;
    ASSERT_TRUE(box.take(out));
    EXPECT_EQ(out, (std::vector<std::uint8_t>{'a', 'b', 'c', 'd'})); // the data as sampled, no BREAK byte
}

TEST(HostOutbox, AnIoThreadTakingWhileTheSimulationPushesLosesNothingUncounted) {
    // Two threads as in the hosts: every byte pushed is either taken, in order, or counted dropped.
    HostOutbox box(64);
    constexpr unsigned kBytes = 200'000;
    std::vector<std::uint8_t> got, chunk;
    std::thread io([&] {
        while (got.size() + box.counters().dropped < kBytes)
            if (box.take(chunk)) got.insert(got.end(), chunk.begin(), chunk.end());
    });
    for (unsigned i = 0; i < kBytes; ++i) box.push(rx(static_cast<std::uint8_t>(i)));
    io.join();
    EXPECT_EQ(got.size() + box.counters().dropped, kBytes);
    // Order kept: each byte taken is a later one than the one before it (mod 256, gaps = drops).
    std::uint64_t index = 0;
    for (std::size_t k = 0; k < got.size(); ++k) {
        if (k > 0) ++index;
        while (static_cast<std::uint8_t>(index) != got[k]) ++index;
    }
    EXPECT_LT(index, kBytes);
}

TEST(HostOutbox, ABoundOfZeroIsRefused) { EXPECT_THROW(HostOutbox(0), std::invalid_argument); }
