// The firmware's protocol on the plain 8086 core with the fake board: the test plays the host
// (bytes into 82510 #p, bytes out of TXD) and the main CPU (DP-RAM and the mailbox words).
#include "fake_board.h"
#include "models/plumbing/hex.h"
#include "tests/support/sc_test.h"

#include <string>

namespace {

using namespace fakeboard;

const char SOH = 0x01, STX = 0x02, ETX = 0x03, EOT = 0x04, ENQ = 0x05, ACK = 0x06, NAK = 0x15;

/// The low byte of `v` as two hex digits, as a frame carries its BCH and checksum.
std::string hex2(unsigned v) { return rcsim::hex(v & 0xFF); }

// SOH T1 T2 STX B1 B2 data C1 C2 ETX; checksum = sum of T1 .. last data byte.
std::string frame(const std::string& token, const std::string& data, unsigned bch = 0, int sum_delta = 0) {
    std::string body = token + STX + hex2(bch) + data;
    unsigned sum = 0;
    for (unsigned char c : body) sum += c;
    return std::string(1, SOH) + body + hex2(sum + sum_delta) + ETX;
}

// A booted fake board.
struct Booted : FakeBoard {
    Booted() { run_ms(5); }

    /// Host: ENQ, expect ACK; then the frame (without waiting for anything).
    void host_frame(unsigned p, const std::string& f, double char_us = kCharUs9600) {
        host_send(p, std::string(1, ENQ), char_us);
        run_until([&] { return !uart[p].tx.empty(); }, 5);
        ASSERT_EQ(host_take(p), std::string(1, ACK)) << "port " << p;
        host_send(p, f, char_us);
    }
    /// Main CPU: wait for 0x1p, copy the chunk, free pflag on the last one, answer 0x2p.
    /// Returns the bytes of the frame (several chunks) or "" when no chunk came within `ms`.
    std::string main_receive_frame(unsigned p, double ms = 100) {
        std::string got;
        for (;;) {
            std::uint8_t w = 0;
            if (!run_until([&] { return !posted.empty(); }, ms)) return got;
            main_take_word(w);
            EXPECT_EQ(w, 0x10 | p);
            if (w != (0x10 | p)) return got;
            EXPECT_EQ(pflag(p), 1) << "EXT_USE while the comm CPU writes";
            const std::string c = main_read_chunk(p);
            got += c;
            const bool last = c.back() == ETX;
            if (last) dp[dl::pflag_addr(p)] = dl::pflag_free; // the reader frees pflag
            else EXPECT_EQ(c.size(), chunk) << "a chunk without ETX is full";
            main_word(std::uint8_t(0x20 | p));
            if (last) return got;
        }
    }
};

TEST(FirmwareProtocol, GoodFrameGetsEotAndReachesTheMainCpuIntact) {
    Booted b;
    const std::string f = frame("EC", "HELLO,123");
    b.host_frame(1, f);
    b.run_ms(2);
    EXPECT_EQ(b.host_take(1), std::string(1, EOT));
    EXPECT_EQ(b.main_receive_frame(1), f);
    b.run_ms(5);
    EXPECT_EQ(b.step(1), 0);
    EXPECT_EQ(b.pflag(1), 0);
    EXPECT_EQ(b.var16(fw::data::n_good, 1), 1u);
    EXPECT_TRUE(b.posted.empty());
}

TEST(FirmwareProtocol, BadChecksumGetsNakAndNothingIsDelivered) {
    Booted b;
    b.host_frame(0, frame("EC", "ABC", 0, +1));
    b.run_ms(2);
    EXPECT_EQ(b.host_take(0), std::string(1, NAK));
    b.run_ms(20);
    EXPECT_TRUE(b.posted.empty()) << "a short dropped frame never reaches DP-RAM";
    EXPECT_EQ(b.pflag(0), 0);
    EXPECT_EQ(b.step(0), 0);
    EXPECT_EQ(b.var16(fw::data::n_nak, 0), 1u);
}

TEST(FirmwareProtocol, ParityErrorGetsNak) {
    Booted b;
    const std::string f = frame("ST", "");
    b.host_send(2, std::string(1, ENQ));
    ASSERT_EQ(b.host_take(2), std::string(1, ACK));
    for (std::size_t i = 0; i < f.size(); ++i) {
        b.host_byte(2, std::uint8_t(f[i]), i == 4 ? 0x04 : 0); // parity error on B1
        b.run_us(kCharUs9600);
    }
    b.run_ms(2);
    EXPECT_EQ(b.host_take(2), std::string(1, NAK));
    b.run_ms(10);
    EXPECT_TRUE(b.posted.empty());
    EXPECT_EQ(b.var16(fw::data::n_lerr, 2), 1u);
}

TEST(FirmwareProtocol, CharacterOutsideTheAllowedSetGetsNak) {
    Booted b;
    std::string f = frame("EC", "AB");
    f[6] = char(0x7F); // DEL is not printable (checksum recomputed below so only the set fails)
    unsigned sum = 0;
    for (std::size_t i = 1; i < f.size() - 3; ++i) sum += std::uint8_t(f[i]);
    f.replace(f.size() - 3, 2, hex2(sum));
    b.host_frame(0, f);
    b.run_ms(2);
    EXPECT_EQ(b.host_take(0), std::string(1, NAK));
}

TEST(FirmwareProtocol, EnqWithALineErrorGetsNak) {
    Booted b;
    b.host_byte(0, ENQ, 0x08); // framing error
    b.run_ms(1);
    EXPECT_EQ(b.host_take(0), std::string(1, NAK));
    EXPECT_EQ(b.step(0), 0);
    EXPECT_EQ(b.pflag(0), 0);
    b.host_byte(0, ENQ);
    b.run_ms(1);
    EXPECT_EQ(b.host_take(0), std::string(1, ACK));
}

TEST(FirmwareProtocol, LostAckOfTheLastChunkIsRecoveredThroughPflag) {
    Booted b;
    const std::string f = frame("EC", "ACKLOST");
    b.host_frame(2, f);
    ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 20));
    std::uint8_t w = 0;
    b.main_take_word(w);
    EXPECT_EQ(b.main_read_chunk(2), f);
    b.dp[dl::pflag_addr(2)] = dl::pflag_free; // the main CPU frees pflag ... and its 0x22 word is overwritten
    b.main_word(0x21);       // by a word for another port (here: an unexpected ACK, ignored)
    ASSERT_TRUE(b.run_until([&] { return b.step(2) == 0; }, 20));
    EXPECT_TRUE(b.posted.empty()) << "no reset, nothing lost";
    EXPECT_EQ(b.uart[2].resets, 1u);
    EXPECT_EQ(b.var16(fw::data::n_implicit), 1u);
}

TEST(FirmwareProtocol, ChunkNeverAcknowledgedResetsThePort) {
    Booted b;
    b.host_frame(0, frame("EC", "LOST"));
    ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 20));
    std::uint8_t w = 0;
    b.main_take_word(w);
    EXPECT_EQ(w, 0x10);
    // the main CPU never answers: after DP_ACK_MS the port is reset and 0x30 goes out
    EXPECT_FALSE(b.run_until([&] { return !b.posted.empty(); }, 900));
    ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 200));
    b.main_take_word(w);
    EXPECT_EQ(w, 0x30);
    EXPECT_EQ(b.step(0), 0);
    EXPECT_EQ(b.pflag(0), 0);
    EXPECT_EQ(b.uart[0].resets, 2u);
}

TEST(FirmwareProtocol, T2GapDropsThePartialFrame) {
    Booted b;
    const std::string f = frame("EC", "PARTIAL");
    b.host_frame(0, f.substr(0, 6));
    b.run_ms(25); // more than T2 = 20 ms
    EXPECT_EQ(b.step(0), 0);
    EXPECT_EQ(b.pflag(0), 0);
    EXPECT_EQ(b.var16(fw::data::n_gap, 0), 1u);
    EXPECT_EQ(b.host_take(0), "") << "no answer to a frame that timed out";
    // the rest arriving late is not taken for a frame
    b.host_send(0, f.substr(6));
    b.run_ms(5);
    EXPECT_EQ(b.host_take(0), "");
    EXPECT_TRUE(b.posted.empty());
    // a gap shorter than T2 is fine
    b.host_frame(0, f.substr(0, 6));
    b.run_ms(15);
    b.host_send(0, f.substr(6));
    b.run_ms(2);
    EXPECT_EQ(b.host_take(0), std::string(1, EOT));
}

TEST(FirmwareProtocol, EnqWhileTheAreaIsBusyGetsNak) {
    Booted b;
    b.dp[dl::pflag_addr(1)] = dl::pflag_rbt_use; // the main CPU is writing port 1's area
    b.host_send(1, std::string(1, ENQ));
    b.run_ms(1);
    EXPECT_EQ(b.host_take(1), std::string(1, NAK));
    EXPECT_EQ(b.step(1), 0);
    EXPECT_EQ(b.var16(fw::data::n_busy, 1), 1u);
    b.dp[dl::pflag_addr(1)] = dl::pflag_free;
    b.host_send(1, std::string(1, ENQ));
    b.run_ms(1);
    EXPECT_EQ(b.host_take(1), std::string(1, ACK));
    EXPECT_EQ(b.pflag(1), 1);
}

TEST(FirmwareProtocol, LongFrameCrossesDpramInChunksIntact) {
    Booted b;
    std::string data;
    for (int i = 0; data.size() < 3000; ++i) data += std::to_string(i) + ",";
    data.resize(3000);
    const std::string f = frame("PU", data);
    // the main CPU consumes chunks while the frame is still arriving
    std::string got;
    b.host_byte(0, ENQ);
    ASSERT_TRUE(b.run_until([&] { return !b.uart[0].tx.empty(); }, 5));
    ASSERT_EQ(b.host_take(0), std::string(1, ACK));
    std::size_t sent = 0;
    while (sent < f.size() || got.empty() || got.back() != ETX) {
        if (sent < f.size()) b.host_byte(0, std::uint8_t(f[sent++]));
        b.run_us(400);
        std::uint8_t w;
        while (b.main_take_word(w)) {
            ASSERT_EQ(w, 0x10);
            const std::string c = b.main_read_chunk(0);
            got += c;
            if (c.back() == ETX) b.dp[dl::pflag_addr(0)] = dl::pflag_free;
            b.main_word(0x20);
        }
        ASSERT_LT(b.now(), 3 * clk_hz) << "stuck";
    }
    EXPECT_EQ(got.size(), f.size());
    EXPECT_EQ(got, f);
    EXPECT_EQ(b.host_take(0), std::string(1, EOT));
    b.run_ms(2);
    EXPECT_EQ(b.step(0), 0);
}

TEST(FirmwareProtocol, OverlongFrameGetsNakAndTheMainCpuIsToldToDropIt) {
    Booted b;
    const std::string f = frame("EC", std::string(8193, 'x'));
    b.host_byte(0, ENQ);
    ASSERT_TRUE(b.run_until([&] { return !b.uart[0].tx.empty(); }, 5));
    ASSERT_EQ(b.host_take(0), std::string(1, ACK));
    std::size_t sent = 0;
    std::string words;
    while (sent < f.size()) {
        b.host_byte(0, std::uint8_t(f[sent++]));
        b.run_us(700);
        std::uint8_t w;
        while (b.main_take_word(w)) {
            words += char(w);
            if (w == 0x10) b.main_word(0x20);
        }
    }
    std::uint8_t w;
    b.run_until([&] {
        while (b.main_take_word(w)) {
            words += char(w);
            if (w == 0x10) b.main_word(0x20);
        }
        return !words.empty() && words.back() == char(0x30);
    }, 300);
    EXPECT_EQ(b.host_take(0), std::string(1, NAK));
    ASSERT_FALSE(words.empty());
    EXPECT_EQ(words.back(), char(0x30)) << "0x30 tells the main CPU to drop the partial frame";
    EXPECT_EQ(b.pflag(0), 0);
    EXPECT_EQ(b.step(0), 0);
}

// Main CPU -> host: a response frame in one chunk.
TEST(FirmwareProtocol, ResponseFrameReachesTheHost) {
    Booted b;
    const std::string f = frame("ST", "RUN,IDLE,1,2,3,4");
    b.main_write_chunk(2, f, true);
    ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 10));
    std::uint8_t w = 0;
    ASSERT_TRUE(b.main_take_word(w));
    EXPECT_EQ(w, 0x22) << "chunk consumed";
    EXPECT_EQ(b.pflag(2), 0) << "the reader frees pflag with the last chunk";
    EXPECT_EQ(b.dp[dl::int2ext], 0) << "int2ext emptied after reading";
    ASSERT_TRUE(b.run_until([&] { return !b.uart[2].tx.empty(); }, 10));
    EXPECT_EQ(b.host_take(2), std::string(1, ENQ));
    b.run_ms(0.2);
    EXPECT_EQ(b.step(2), 11);
    b.host_send(2, std::string(1, ACK));
    EXPECT_TRUE(b.run_until([&] { return b.step(2) == 13; }, 20));
    EXPECT_EQ(b.host_take(2), f);
    b.host_send(2, std::string(1, EOT));
    b.run_ms(1);
    EXPECT_EQ(b.step(2), 0);
    EXPECT_EQ(b.var16(fw::data::n_sent, 2), 1u);
}

TEST(FirmwareProtocol, ResponseLeavesWithoutGapsWhileAChunkIsCopied) {
    Booted b;
    const cycles_t char_cycles = cycles_t(kCharUs9600) * cycles_per_us;
    b.uart[0].tx_char_cycles = char_cycles; // a real 9600 bps transmitter with its 4-byte FIFO
    const std::string f = frame("PD", std::string(300, 'r'));
    b.main_write_chunk(0, f, true);
    ASSERT_TRUE(b.run_until([&] { return !b.uart[0].tx.empty(); }, 60));
    ASSERT_EQ(b.host_take(0), std::string(1, ENQ));
    const std::size_t first = b.uart[0].tx_at.size();
    b.host_send(0, std::string(1, ACK));
    // while the frame goes out, the main CPU hands over a full chunk for port 1 (a ~20 ms copy
    // in the DP-RAM ISR) and port 2 receives a frame
    b.run_ms(5);
    b.main_write_chunk(1, std::string(FakeBoard::chunk, 'x'), true);
    b.host_frame(2, frame("EC", std::string(40, 'e')));
    ASSERT_TRUE(b.run_until([&] { return b.step(0) == 13; }, 1000));
    b.run_ms(10);
    EXPECT_EQ(b.host_take(0), f);
    EXPECT_EQ(b.uart[0].tx_overflows, 0u);
    cycles_t worst = 0;
    for (std::size_t i = first + 1; i < b.uart[0].tx_at.size(); ++i)
        worst = std::max(worst, b.uart[0].tx_at[i] - b.uart[0].tx_at[i - 1]);
    EXPECT_EQ(worst, char_cycles) << "characters back to back: the FIFO never ran dry";
}

TEST(FirmwareProtocol, MultiChunkResponseAndQueuedFramesGoOutInOrder) {
    Booted b;
    const std::string big = frame("PD", std::string(700, 'p'));
    const std::string small = frame("EC", "2");
    // three chunks of `big`, then `small`, each after the ACK of the previous chunk
    for (std::size_t off = 0; off < big.size(); off += FakeBoard::chunk) {
        b.main_write_chunk(0, big.substr(off, FakeBoard::chunk), off == 0);
        std::uint8_t w = 0;
        ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 60)); // ~70 us per byte
        b.main_take_word(w);
        ASSERT_EQ(w, 0x20);
    }
    EXPECT_EQ(b.pflag(0), 0);
    b.main_write_chunk(0, small, true);
    ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 10));
    b.posted.clear();
    std::string out;
    for (int frames = 0; frames < 2; ++frames) {
        ASSERT_TRUE(b.run_until([&] { return !b.uart[0].tx.empty(); }, 100));
        ASSERT_EQ(b.host_take(0), std::string(1, ENQ));
        b.host_send(0, std::string(1, ACK));
        b.run_until([&] { return b.step(0) == 13; }, 100);
        out += b.host_take(0);
        b.host_send(0, std::string(1, EOT));
    }
    EXPECT_EQ(out, big + small);
}

TEST(FirmwareProtocol, NakAndTimeoutAreRetriedWithBackoffThenReported) {
    Booted b;
    const std::string f = frame("EC", "R"), next = frame("EC", "NEXT");
    b.main_write_chunk(1, f, true);
    ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 10));
    b.posted.clear();
    b.main_write_chunk(1, next, true); // queued behind f
    ASSERT_TRUE(b.run_until([&] { return !b.uart[1].tx.empty() && !b.posted.empty(); }, 10));
    b.posted.clear();
    ASSERT_EQ(b.host_take(1), std::string(1, ENQ));
    // attempt 1: NAK -> next ENQ about 10 ms later
    const cycles_t t_nak = b.now();
    b.host_send(1, std::string(1, NAK));
    ASSERT_TRUE(b.run_until([&] { return !b.uart[1].tx.empty(); }, 30));
    const double gap1 = double(b.now() - t_nak) / cycles_per_us / 1000.0;
    EXPECT_GE(gap1, 9.0);
    EXPECT_LE(gap1, 12.5);
    ASSERT_EQ(b.host_take(1), std::string(1, ENQ));
    // attempt 2: no answer -> T1 then 20 ms back-off. The fake board's transmitter is instantaneous,
    // so the ENQ has left at once; T1 (50 ms) ends at the START bit of the answer, which the
    // receiver has one 9600-bps character (1.146 ms) later: the firmware waits more than 50 +
    // 1.146 ms, and at most 50 + 2 (the character in whole ticks) + 1 (tick phase) ms, plus the
    // main loop.
    const cycles_t t_enq = b.now();
    ASSERT_TRUE(b.run_until([&] { return !b.uart[1].tx.empty(); }, 100));
    const double gap2 = double(b.now() - t_enq) / cycles_per_us / 1000.0;
    EXPECT_GE(gap2, 50.0 + 1.146 + 20.0);
    EXPECT_LE(gap2, 50.0 + 2.0 + 1.0 + 20.0 + 0.5);
    ASSERT_EQ(b.host_take(1), std::string(1, ENQ));
    // attempt 3: ACK, frame, then NAK for the frame -> whole frame again after 30 ms
    b.host_send(1, std::string(1, ACK));
    b.run_until([&] { return b.step(1) == 13; }, 50);
    EXPECT_EQ(b.host_take(1), f);
    b.host_send(1, std::string(1, NAK));
    ASSERT_TRUE(b.run_until([&] { return !b.uart[1].tx.empty(); }, 50));
    ASSERT_EQ(b.host_take(1), std::string(1, ENQ));
    // attempt 4 (third retry): NAK -> give up on f only: 0x51 to the main CPU (given up, but it
    // had left whole in attempt 3: the host may have it), no port reset; `next' goes out.
    b.host_send(1, std::string(1, NAK));
    std::uint8_t w = 0;
    ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 5));
    ASSERT_TRUE(b.main_take_word(w));
    EXPECT_EQ(w, 0x51);
    EXPECT_EQ(b.var16(fw::data::n_retry, 1), 3u);
    EXPECT_EQ(b.var16(fw::data::n_fail, 1), 1u);
    EXPECT_EQ(b.var16(fw::data::n_reset, 1), 0u) << "a give-up does not reset the port";
    ASSERT_TRUE(b.run_until([&] { return !b.uart[1].tx.empty(); }, 10));
    EXPECT_EQ(b.host_take(1), std::string(1, ENQ)) << "the next queued frame";
    b.host_send(1, std::string(1, ACK));
    ASSERT_TRUE(b.run_until([&] { return b.step(1) == 13; }, 50));
    EXPECT_EQ(b.host_take(1), next);
    b.host_send(1, std::string(1, EOT));
    b.run_ms(1);
    EXPECT_EQ(b.step(1), 0);
    EXPECT_EQ(b.var16(fw::data::n_sent, 1), 1u);
    EXPECT_FALSE(b.main_take_word(w)) << "no 0x31: nothing else was dropped";
}

// A give-up before the frame ever left whole (every ENQ refused) says so: 0x4p.
TEST(FirmwareProtocol, GiveUpOfAFrameThatNeverLeftIsReportedAsUnsent) {
    Booted b;
    b.main_write_chunk(2, frame("EC", "NEVER"), true);
    ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 10));
    b.posted.clear();
    for (int attempt = 0; attempt < 4; ++attempt) {
        ASSERT_TRUE(b.run_until([&] { return !b.uart[2].tx.empty(); }, 100)) << attempt;
        ASSERT_EQ(b.host_take(2), std::string(1, ENQ)) << attempt;
        b.host_send(2, std::string(1, NAK));
    }
    std::uint8_t w = 0;
    ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 5));
    ASSERT_TRUE(b.main_take_word(w));
    EXPECT_EQ(w, 0x42);
    EXPECT_EQ(b.step(2), 0);
    b.run_ms(100);
    EXPECT_EQ(b.host_take(2), "") << "nothing else queued";
}

TEST(FirmwareProtocol, EnqCollisionTheExternalSystemWins) {
    Booted b;
    const std::string mine = frame("ST", "0");
    b.main_write_chunk(0, mine, true);
    ASSERT_TRUE(b.run_until([&] { return !b.uart[0].tx.empty(); }, 10));
    b.posted.clear();
    ASSERT_EQ(b.host_take(0), std::string(1, ENQ));
    b.run_ms(0.2);
    EXPECT_EQ(b.step(0), 11);
    // the host sends its own ENQ instead of answering
    const std::string theirs = frame("EC", "HOST");
    b.host_send(0, std::string(1, ENQ));
    EXPECT_EQ(b.host_take(0), std::string(1, ACK)) << "the external system wins";
    EXPECT_EQ(b.step(0), 1);
    b.host_send(0, theirs);
    b.run_ms(2);
    EXPECT_EQ(b.host_take(0), std::string(1, EOT));
    EXPECT_EQ(b.main_receive_frame(0), theirs);
    // then the comm CPU tries its own frame again
    ASSERT_TRUE(b.run_until([&] { return !b.uart[0].tx.empty(); }, 20));
    EXPECT_EQ(b.host_take(0), std::string(1, ENQ));
    b.host_send(0, std::string(1, ACK));
    b.run_until([&] { return b.step(0) == 13; }, 50);
    EXPECT_EQ(b.host_take(0), mine);
    EXPECT_EQ(b.var16(fw::data::n_coll, 0), 1u);
}

TEST(FirmwareProtocol, CollisionWhileTheAreaIsBusyKeepsOurAttempt) {
    Booted b;
    const std::string mine = frame("ST", "1");
    b.main_write_chunk(0, mine, true);
    ASSERT_TRUE(b.run_until([&] { return !b.uart[0].tx.empty(); }, 10));
    ASSERT_EQ(b.host_take(0), std::string(1, ENQ));
    b.dp[dl::pflag_addr(0)] = dl::pflag_rbt_use; // the main CPU has started writing the next frame for port 0
    b.host_send(0, std::string(1, ENQ));
    EXPECT_EQ(b.host_take(0), std::string(1, NAK));
    EXPECT_EQ(b.step(0), 11) << "our ENQ still stands";
    b.host_send(0, std::string(1, ACK));
    ASSERT_TRUE(b.run_until([&] { return b.step(0) == 13; }, 50));
    EXPECT_EQ(b.host_take(0), mine);
    EXPECT_EQ(b.var16(fw::data::n_coll, 0), 0u);
}

TEST(FirmwareProtocol, FullTransmitQueueHoldsTheChunkUnacknowledged) {
    Booted b;
    // the host does not answer our ENQ yet, so frames pile up: 8 fit, the 9th waits in DP-RAM
    for (int i = 0; i < 9; ++i) {
        b.main_write_chunk(0, frame("EC", std::to_string(i)), true);
        const bool acked = b.run_until([&] { return !b.posted.empty(); }, 5);
        EXPECT_EQ(acked, i < 8) << i;
        if (acked) {
            std::uint8_t w;
            b.main_take_word(w);
            EXPECT_EQ(w, 0x20);
        }
    }
    EXPECT_EQ(b.var8(fw::data::tx_have), 8);
    EXPECT_EQ(b.var8(fw::data::chunk_pending), 1);
    ASSERT_EQ(b.host_take(0), std::string(1, ENQ));
    b.host_send(0, std::string(1, ACK));
    ASSERT_TRUE(b.run_until([&] { return b.step(0) == 13; }, 50));
    EXPECT_EQ(b.host_take(0), frame("EC", "0"));
    b.host_send(0, std::string(1, EOT));
    // one frame gone: the waiting chunk is taken and acknowledged
    ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 10));
    EXPECT_EQ(b.posted.front(), 0x20);
    EXPECT_EQ(b.var8(fw::data::chunk_pending), 0);
    // and all nine frames reach the host in order
    std::string out;
    for (int i = 1; i < 9; ++i) {
        ASSERT_TRUE(b.run_until([&] { return !b.uart[0].tx.empty(); }, 20)) << i;
        ASSERT_EQ(b.host_take(0), std::string(1, ENQ));
        b.host_send(0, std::string(1, ACK));
        ASSERT_TRUE(b.run_until([&] { return b.step(0) == 13; }, 50));
        out += b.host_take(0);
        b.host_send(0, std::string(1, EOT));
    }
    std::string want;
    for (int i = 1; i < 9; ++i) want += frame("EC", std::to_string(i));
    EXPECT_EQ(out, want);
}

TEST(FirmwareProtocol, AbandonedMainCpuClaimIsFreedAfterASecond) {
    Booted b;
    // the main CPU writes the first chunk of a two-chunk frame and then gives it up
    b.main_write_chunk(2, std::string(FakeBoard::chunk, 'a'), true);
    ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 60));
    b.posted.clear();
    EXPECT_EQ(b.pflag(2), 2);
    b.run_ms(900);
    EXPECT_EQ(b.pflag(2), 2) << "not before AREA_STALE_MS";
    b.run_ms(200);
    EXPECT_EQ(b.pflag(2), 0);
    EXPECT_EQ(b.var16(fw::data::n_stale, 2), 1u);
    EXPECT_EQ(b.var16(fw::data::tx_used, 2), 0u) << "the partial frame is dropped";
    // the next frame goes out intact, without the abandoned bytes in front
    const std::string f = frame("EC", "NEXT");
    b.main_write_chunk(2, f, true);
    ASSERT_TRUE(b.run_until([&] { return !b.uart[2].tx.empty(); }, 20));
    ASSERT_EQ(b.host_take(2), std::string(1, ENQ));
    b.host_send(2, std::string(1, ACK));
    ASSERT_TRUE(b.run_until([&] { return b.step(2) == 13; }, 50));
    EXPECT_EQ(b.host_take(2), f);
}

TEST(FirmwareProtocol, PortResetByMailboxWord) {
    Booted b;
    b.host_frame(2, frame("EC", "X").substr(0, 4)); // a frame in progress
    EXPECT_EQ(b.step(2), 1);
    EXPECT_EQ(b.pflag(2), 1);
    const unsigned resets = b.uart[2].resets;
    b.main_word(0x32);
    b.run_ms(2);
    EXPECT_EQ(b.uart[2].resets, resets + 1) << "82510 #2 re-initialised (ICM software reset)";
    EXPECT_EQ(b.uart[2].lcr, 0x1B);
    EXPECT_EQ(b.uart[2].ger, 0x05);
    EXPECT_EQ(b.step(2), 0);
    EXPECT_EQ(b.pflag(2), 0);
    EXPECT_TRUE(b.posted.empty()) << "a reset the main CPU asked for is not echoed";
    EXPECT_EQ(b.uart[0].resets, 1u) << "other ports untouched";
    // the port works afterwards
    b.host_frame(2, frame("EC", "Y"));
    b.run_ms(2);
    EXPECT_EQ(b.host_take(2), std::string(1, EOT));
}

TEST(FirmwareProtocol, PortResetDuringAChunkWriteLeavesTheAreaFree) {
    Booted b;
    const std::string f = frame("PU", std::string(600, 'w'));
    b.host_byte(0, ENQ);
    ASSERT_TRUE(b.run_until([&] { return !b.uart[0].tx.empty(); }, 5));
    b.host_take(0);
    for (std::size_t i = 0; i < FakeBoard::chunk + 1; ++i) {
        b.host_byte(0, std::uint8_t(f[i]));
        b.run_us(600);
    }
    // the main loop is now writing the first chunk (about 20 ms); the main CPU resets port 0
    b.run_ms(3);
    ASSERT_TRUE(b.posted.empty());
    b.main_word(0x30);
    b.run_ms(40);
    EXPECT_TRUE(b.posted.empty()) << "no chunk word for a port that was reset meanwhile";
    EXPECT_EQ(b.pflag(0), 0);
    EXPECT_EQ(b.step(0), 0);
    EXPECT_EQ(b.var8(fw::data::chunk_out), 0);
    // and the port takes the next frame
    b.host_frame(0, frame("EC", "OK"));
    b.run_ms(2);
    EXPECT_EQ(b.host_take(0), std::string(1, EOT));
}

TEST(FirmwareProtocol, PortResetByBreak) {
    Booted b;
    b.host_frame(1, frame("EC", "X").substr(0, 5));
    EXPECT_EQ(b.step(1), 1);
    b.host_break(1);
    b.run_ms(2);
    EXPECT_EQ(b.uart[1].resets, 2u);
    EXPECT_EQ(b.step(1), 0);
    EXPECT_EQ(b.pflag(1), 0);
    std::uint8_t w = 0;
    ASSERT_TRUE(b.main_take_word(w));
    EXPECT_EQ(w, 0x31) << "the main CPU hears of the reset";
    // a BREAK that goes on is reported again by the chip: no second reset
    b.host_break(1);
    b.run_ms(2);
    EXPECT_EQ(b.uart[1].resets, 2u);
    EXPECT_TRUE(b.posted.empty());
    EXPECT_EQ(b.var16(fw::data::n_break, 1), 2u);
    b.host_frame(1, frame("EC", "Y"));
    b.run_ms(2);
    EXPECT_EQ(b.host_take(1), std::string(1, EOT));
}

TEST(FirmwareProtocol, MailboxWordIsTakenPromptlyEvenDuringAChunkCopy) {
    Booted b;
    b.main_write_chunk(0, std::string(FakeBoard::chunk, 'z'), true); // a full chunk: a long copy
    b.run_ms(3);
    EXPECT_EQ(b.dp[dl::int2ext], 0);
    EXPECT_TRUE(b.posted.empty()) << "still copying";
    // a second word while the copy runs: read (and emptied) within a millisecond
    const cycles_t t = b.now();
    b.main_word(0x31);
    ASSERT_TRUE(b.run_until([&] { return b.dp[dl::int2ext] == 0; }, 5));
    EXPECT_LT(b.int2ext_read_at - t, 1000 * cycles_per_us);
    // the nested handler only asks for the reset (step 4: the port answers nothing but NAK); the
    // main loop runs it once the copy's handler has returned
    ASSERT_TRUE(b.run_until([&] { return b.step(1) == 4; }, 0.1)) << "port 1's reset asked for";
    EXPECT_EQ(b.uart[1].resets, 1u) << "not run inside the handler";
    EXPECT_TRUE(b.posted.empty()) << "port 0 still copying";
    ASSERT_TRUE(b.run_until([&] { return !b.posted.empty(); }, 60));
    EXPECT_EQ(b.posted.front(), 0x20);
    EXPECT_EQ(b.pflag(0), 2) << "not the last chunk: pflag stays with the main CPU";
    ASSERT_TRUE(b.run_until([&] { return b.uart[1].resets == 2u && b.step(1) == 0; }, 5))
        << "then port 1 is reset";
}

TEST(FirmwareProtocol, NextWordWaitsUntilTheMainCpuEmptiedInt2rbt) {
    // Three frames complete at once -> three 0x1p words. When the main CPU empties int2rbt
    // after each read they follow as fast as the chunks are written; when it never does, the
    // comm CPU spaces them by MB_WAIT_MS (5 ticks: at least 4 ms).
    cycles_t min_gap[2] = {~cycles_t(0), ~cycles_t(0)};
    for (int run = 0; run < 2; ++run) {
        Booted b;
        b.main_clears_int2rbt = run == 0;
        const std::string f = frame("EC", "");
        for (unsigned p = 0; p < 3; ++p) b.host_byte(p, ENQ);
        b.run_ms(1.2);
        for (std::size_t i = 0; i < f.size(); ++i) {
            for (unsigned p = 0; p < 3; ++p) b.host_byte(p, std::uint8_t(f[i]));
            b.run_us(kCharUs9600);
        }
        ASSERT_TRUE(b.run_until([&] {
            std::uint8_t w;
            while (b.main_take_word(w)) {}
            return b.posted_at.size() >= 3;
        }, 30));
        for (std::size_t i = 1; i < 3; ++i)
            min_gap[run] = std::min(min_gap[run], b.posted_at[i] - b.posted_at[i - 1]);
    }
    EXPECT_LT(min_gap[0], 1000 * cycles_per_us);
    EXPECT_GE(min_gap[1], 4000 * cycles_per_us); // MB_WAIT_MS = 5 ticks
}

TEST(FirmwareProtocol, ThreePortsAtOnceKeepEveryByte) {
    Booted b;
    const std::string f[3] = {frame("EC", std::string(400, 'a')), frame("EC", std::string(400, 'b')),
                              frame("EC", std::string(400, 'c'))};
    for (unsigned p = 0; p < 3; ++p) b.host_byte(p, ENQ);
    // Three ENQs at once: each ACK is written within ~0.3 ms of its interrupt, and the fake board's
    // instantaneous transmitter makes each transmitter-idle interrupt (T1 starts) follow at
    // once: all three ACKs within two character times (far inside T1).
    ASSERT_TRUE(b.run_until([&] { return b.uart[0].tx.size() && b.uart[1].tx.size() && b.uart[2].tx.size(); },
                            2 * 1.146));
    for (unsigned p = 0; p < 3; ++p) ASSERT_EQ(b.host_take(p), std::string(1, ACK)) << p;
    std::string got[3];
    for (std::size_t i = 0; i < f[0].size(); ++i) {
        for (unsigned p = 0; p < 3; ++p) b.host_byte(p, std::uint8_t(f[p][i]));
        b.run_us(kCharUs9600);
        std::uint8_t w;
        while (b.main_take_word(w)) {
            const unsigned p = w & 0x0F;
            ASSERT_EQ(w & 0xF0, 0x10);
            const std::string c = b.main_read_chunk(p);
            got[p] += c;
            if (c.back() == ETX) b.dp[dl::pflag_addr(p)] = dl::pflag_free;
            b.main_word(std::uint8_t(0x20 | p));
            b.run_us(50);
        }
    }
    auto done = [&] {
        for (unsigned p = 0; p < 3; ++p)
            if (got[p].empty() || got[p].back() != ETX) return false;
        return true;
    };
    b.run_until([&] {
        std::uint8_t w;
        while (b.main_take_word(w)) {
            const unsigned p = w & 0x0F;
            const std::string c = b.main_read_chunk(p);
            got[p] += c;
            if (c.back() == ETX) b.dp[dl::pflag_addr(p)] = dl::pflag_free;
            b.main_word(std::uint8_t(0x20 | p));
        }
        return done();
    }, 500);
    for (unsigned p = 0; p < 3; ++p) {
        EXPECT_EQ(got[p], f[p]) << p;
        EXPECT_EQ(b.host_take(p), std::string(1, EOT)) << p;
        EXPECT_EQ(b.var16(fw::data::n_lerr, p), 0u);
        EXPECT_LE(b.uart[p].rx_high, 2u) << "port " << p << ": the 4-byte FIFO never came close to overrun";
    }
}

} // namespace
