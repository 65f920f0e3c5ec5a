// The figures gathered online (scenarios/verdict/measure.h) against their definitions over the whole
// run's lists, which is how they were computed before they went online: the DP-RAM time per byte
// to the last bit, and the exactly-once frame comparison.
#include "scenarios/verdict/measure.h"
#include "models/clock.h"
#include "tests/support/sc_test.h"

#include <algorithm>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

using namespace rcsim;
using sc_core::sc_time;

namespace {

// ---------------------------------------------------------------------------------------------
// DP-RAM time per byte

struct Chunk {
    unsigned port;
    sc_time first, last;
    std::uint64_t writes = 0, bytes = 0;
};
struct Isr {
    unsigned depth;
    sc_time inta1, iret_done;
};

/// docs/scenarios.md: over every chunk (in the order they began) of two or more writes, the span
/// of its writes less the depth-0 handlers inside it (in completion order), over the gaps.
std::optional<double> per_byte_by_definition(const std::vector<Chunk>& chunks, const std::vector<Isr>& done) {
    double time_us = 0;
    std::uint64_t gaps = 0;
    for (const Chunk& c : chunks) {
        if (c.writes < 2) continue;
        double isr = 0;
        for (const Isr& r : done) {
            if (r.depth != 0) continue;
            const sc_time lo = std::max(c.first, r.inta1), hi = std::min(c.last, r.iret_done);
            if (hi > lo) isr += to_us(hi - lo);
        }
        time_us += to_us(c.last - c.first) - isr;
        gaps += c.writes - 1;
    }
    if (!gaps) return std::nullopt;
    return time_us / static_cast<double>(gaps);
}

/// A random run of the comm CPU, fed to DpramByteTime as a run (the World) does (in bus order) and kept
/// whole for the definition: chunk writes of three ports interleaved in the main program and
/// inside handlers, handlers with nested ones, mailbox words, and chunks left open at the end.
struct RandomRun {
    std::vector<Chunk> chunks;
    std::vector<Isr> done;
    DpramByteTime online;
    std::size_t most_pending = 0;

    explicit RandomRun(std::uint64_t seed, int steps) {
        std::mt19937_64 rng(seed);
        std::uniform_int_distribution<int> action(0, 99);
        // Step lengths: whole clocks of 125 ns, and odd picoseconds like an IR line between clocks.
        auto advance = [&rng](sc_time& t) {
            t += ps(125000 * (1 + rng() % 40) + (rng() % 4 == 0 ? rng() % 125000 : 0));
        };
        sc_time t;
        std::vector<Isr> open; // the probe's stack
        int open_chunk[3] = {-1, -1, -1};
        for (int i = 0; i < steps; ++i) {
            advance(t);
            const int a = action(rng);
            const unsigned port = static_cast<unsigned>(rng() % 3);
            if (a < 45) { // a data write, of one byte or a word
                const unsigned width = 1 + static_cast<unsigned>(rng() % 2);
                if (open_chunk[port] < 0) {
                    open_chunk[port] = static_cast<int>(chunks.size());
                    chunks.push_back({port, t, t});
                }
                Chunk& c = chunks[static_cast<std::size_t>(open_chunk[port])];
                c.last = t;
                ++c.writes;
                c.bytes += width;
                online.data_write(port, t, width);
            } else if (a < 55) { // the 0x1p word
                open_chunk[port] = -1;
                online.chunk_closed(port);
            } else if (a < 75 && open.size() < 3) { // an interrupt is entered
                open.push_back({static_cast<unsigned>(open.size()), t, t});
            } else if (a < 95 && !open.empty()) { // the innermost one returns
                Isr r = open.back();
                open.pop_back();
                r.iret_done = t;
                done.push_back(r);
                if (r.depth == 0) {
                    online.interrupt(r.inta1, r.iret_done);
                    online.settle(); // back in the main program (the probe settles)
                }
            }
            most_pending = std::max(most_pending, online.chunks_pending());
        }
        online.finish(); // interrupts still open at the end are not counted
    }
};

TEST(DpramByteTime, IsTheWholeRunDefinitionToTheLastBit) {
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        RandomRun run(seed, 4000);
        const auto want = per_byte_by_definition(run.chunks, run.done);
        ASSERT_TRUE(want.has_value());
        ASSERT_TRUE(run.online.per_byte_us().has_value());
        EXPECT_EQ(*run.online.per_byte_us(), *want); // exactly, not nearly: the same additions
        std::uint64_t bytes = 0;
        for (const Chunk& c : run.chunks) bytes += c.writes >= 2 ? c.bytes : 0;
        EXPECT_EQ(run.online.bytes(), bytes);
        // Only chunks not yet summed are held: here a few hundred of the run's thousand or so.
        EXPECT_LT(run.most_pending, run.chunks.size());
    }
}

TEST(DpramByteTime, HandlerTimeInsideTheSpanIsNotProcessing) {
    // Writes at 0, 10, 20, 30 us with a handler from 12 to 17 us between them: per byte
    // (30 - 5) / 3 us. A handler after the last write (a mailbox wait) takes nothing away.
    DpramByteTime d;
    d.data_write(1, us(0), 1);
    d.data_write(1, us(10), 1);
    d.interrupt(us(12), us(17));
    d.settle();
    d.data_write(1, us(20), 1);
    d.data_write(1, us(30), 1);
    d.interrupt(us(31), us(40));
    d.chunk_closed(1);
    d.settle();
    d.finish();
    ASSERT_TRUE(d.per_byte_us().has_value());
    EXPECT_DOUBLE_EQ(*d.per_byte_us(), 25.0 / 3.0);
    EXPECT_EQ(d.bytes(), 4u);
    // A chunk of one write has no gap: not measured.
    DpramByteTime one;
    one.data_write(0, us(5), 2);
    one.finish();
    EXPECT_FALSE(one.per_byte_us().has_value());
}

TEST(DpramByteTime, AChunkThatNeverGetsItsMailboxWordHoldsBackABoundedNumber) {
    DpramByteTime d;
    d.data_write(0, us(1), 1); // port 0: reset while copying, no 0x1p ever
    for (int i = 0; i < 3000; ++i) {
        d.data_write(1, us(10 + 3 * i), 1);
        d.data_write(1, us(11 + 3 * i), 1);
        d.chunk_closed(1);
        d.settle();
        ASSERT_LE(d.chunks_pending(), DpramByteTime::kMaxPending + 1);
    }
    d.finish();
    // Every port-1 chunk is one gap of 1 us; the lone write of port 0 counts for nothing.
    ASSERT_TRUE(d.per_byte_us().has_value());
    EXPECT_DOUBLE_EQ(*d.per_byte_us(), 1.0);
    EXPECT_EQ(d.bytes(), 6000u);
}

} // namespace
