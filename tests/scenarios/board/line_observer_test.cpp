// The line observer's decoder fed byte by byte, as the receivers on each side decoded them, and
// its sequence comparison. Frames are built with the codec (docs/system.md §5.3), so the expected
// counts follow from the transfers of docs/system.md §5.2 written out in each test.
#include "scenarios/board/line_observer.h"

#include <gtest/gtest.h>

#include <string>

using namespace rcsim;
using proto::ACK;
using proto::ENQ;
using proto::EOT;
using proto::NAK;

namespace {

constexpr auto H = LineObserver::host_to_controller;
constexpr auto C = LineObserver::controller_to_host;

proto::Frame cmd(const std::string& data) { return proto::Frame{"EC", 0, data}; }
std::string wire(const proto::Frame& f) { return proto::encode(f); }
std::string ctl(std::uint8_t b) { return std::string(1, static_cast<char>(b)); }

void send(LineObserver& o, LineObserver::Dir d, const std::string& bytes) {
    for (unsigned char b : bytes) o.line_char(d, b, false);
}

/// One whole host transfer: ENQ, ACK, the frame, EOT (docs/system.md §5.2).
void host_transfer(LineObserver& o, const proto::Frame& f) {
    send(o, H, ctl(ENQ));
    send(o, C, ctl(ACK));
    send(o, H, wire(f));
    send(o, C, ctl(EOT));
}

void controller_transfer(LineObserver& o, const proto::Frame& f) {
    send(o, C, ctl(ENQ));
    send(o, H, ctl(ACK));
    send(o, C, wire(f));
    send(o, H, ctl(EOT));
}

} // namespace

TEST(LineObserver, AWholeTransferIsOneFrameOfferedAndAcknowledged) {
    LineObserver o;
    const proto::Frame f = cmd("HELLO");
    host_transfer(o, f);
    o.main_received(frame_key(f));
    o.finish();
    const auto& h = o.counts(H);
    EXPECT_EQ(h.enqs, 1u);
    EXPECT_EQ(h.frames_offered, 1u);
    EXPECT_EQ(h.frames_eot, 1u);
    EXPECT_EQ(h.frames_bad + h.naks + h.retries + h.abandoned, 0u);
    EXPECT_EQ(o.counts(C).enqs, 0u);
    EXPECT_EQ(o.commands().sent, 1u);
    EXPECT_EQ(o.commands().matched, 1u);
    EXPECT_EQ(o.commands().mismatches(), 0u);
}

TEST(LineObserver, EnqsThatCrossAreOneCollision) {
    LineObserver o;
    send(o, C, ctl(ENQ)); // the controller asks to send a response...
    send(o, H, ctl(ENQ)); // ...while the host asks too: the host wins (§6.3)
    send(o, C, ctl(ACK));
    send(o, H, wire(cmd("A")));
    send(o, C, ctl(EOT));
    EXPECT_EQ(o.enq_collisions(), 1u);
    EXPECT_EQ(o.counts(H).frames_eot, 1u);
    EXPECT_EQ(o.counts(C).enqs, 1u);
    EXPECT_EQ(o.counts(C).frames_offered, 0u);
}

TEST(LineObserver, ANakedFrameSentAgainIsARetry) {
    LineObserver o;
    const proto::Frame f = cmd("RETRY");
    send(o, H, ctl(ENQ));
    send(o, C, ctl(ACK));
    send(o, H, wire(f));
    send(o, C, ctl(NAK)); // dropped by the receiver; a retry is a new transfer (§6.2)
    host_transfer(o, f);
    o.finish();
    const auto& h = o.counts(H);
    EXPECT_EQ(h.enqs, 2u);
    EXPECT_EQ(h.frames_offered, 2u);
    EXPECT_EQ(h.naks, 1u);
    EXPECT_EQ(h.retries, 1u);
    EXPECT_EQ(h.frames_eot, 1u);
    EXPECT_EQ(h.abandoned, 0u);
    EXPECT_EQ(o.commands().sent, 1u); // the host was told once
}

TEST(LineObserver, ANakedEnqCountsAsNak) {
    LineObserver o;
    send(o, H, ctl(ENQ));
    send(o, C, ctl(NAK));
    EXPECT_EQ(o.counts(H).naks, 1u);
    EXPECT_EQ(o.counts(H).frames_offered, 0u);
}

TEST(LineObserver, AWrongChecksumIsABadFrameNeverDelivered) {
    LineObserver o;
    std::string bad = wire(cmd("HELLO"));
    bad[bad.size() - 2] = bad[bad.size() - 2] == '0' ? '1' : '0'; // C2: the sum no longer fits
    send(o, H, ctl(ENQ));
    send(o, C, ctl(ACK));
    send(o, H, bad);
    send(o, C, ctl(NAK));
    o.finish();
    EXPECT_EQ(o.counts(H).frames_offered, 1u);
    EXPECT_EQ(o.counts(H).frames_bad, 1u);
    EXPECT_EQ(o.counts(H).naks, 1u);
    EXPECT_EQ(o.counts(H).frames_eot, 0u);
    EXPECT_EQ(o.commands().sent, 0u);
}

TEST(LineObserver, AByteWithALineErrorSpoilsItsFrame) {
    LineObserver o;
    const std::string w = wire(cmd("PARITY"));
    send(o, H, ctl(ENQ));
    send(o, C, ctl(ACK));
    for (std::size_t i = 0; i < w.size(); ++i) o.line_char(H, static_cast<unsigned char>(w[i]), i == 4);
    EXPECT_EQ(o.counts(H).frames_bad, 1u);
}

TEST(LineObserver, ADifferentFrameAfterOneWithoutEotAbandonsIt) {
    LineObserver o;
    send(o, H, ctl(ENQ));
    send(o, C, ctl(ACK));
    send(o, H, wire(cmd("FIRST"))); // no answer: the sender gives it up after its retries
    host_transfer(o, cmd("SECOND"));
    send(o, H, ctl(ENQ));
    send(o, C, ctl(ACK));
    send(o, H, wire(cmd("THIRD"))); // unanswered when the run ends
    o.finish();
    EXPECT_EQ(o.counts(H).abandoned, 2u);
    EXPECT_EQ(o.counts(H).retries, 0u);
    EXPECT_EQ(o.counts(H).frames_eot, 1u);
}

TEST(LineObserver, AFrameCutByABreakIsNoFrame) {
    LineObserver o;
    const std::string w = wire(cmd("CUT"));
    send(o, H, w.substr(0, 4));
    o.line_break(H);
    send(o, H, w.substr(4)); // the rest, without its SOH, is no frame
    EXPECT_EQ(o.counts(H).frames_offered, 0u);
    EXPECT_EQ(o.breaks(), 1u);
}

TEST(LineObserver, ASwallowedEotMakesADuplicateAtTheMainCpu) {
    LineObserver o;
    const proto::Frame f = cmd("TWICE"), g = cmd("NEXT");
    send(o, H, ctl(ENQ));
    send(o, C, ctl(ACK));
    send(o, H, wire(f));
    // The controller accepted f and forwarded it; its EOT never reached the host.
    o.main_received(frame_key(f));
    host_transfer(o, f); // the host sends f again; the controller cannot tell
    o.main_received(frame_key(f));
    host_transfer(o, g);
    o.main_received(frame_key(g));
    o.finish();
    EXPECT_EQ(o.counts(H).retries, 1u);
    EXPECT_EQ(o.commands().sent, 2u);     // f and g, as the host was told
    EXPECT_EQ(o.commands().received, 3u); // f, f, g
    EXPECT_EQ(o.commands().duplicates, 1u);
    EXPECT_EQ(o.commands().lost, 0u);
    EXPECT_EQ(o.commands().mismatches(), 1u);
}

TEST(LineObserver, ACommandTheHostGaveUpOnButTheMainCpuGotIsUnexpected) {
    LineObserver o;
    const proto::Frame f = cmd("GIVEN-UP"), g = cmd("NEXT");
    for (int attempt = 0; attempt < 4; ++attempt) { // every EOT swallowed: the host gives up (§6.2)
        send(o, H, ctl(ENQ));
        send(o, C, ctl(ACK));
        send(o, H, wire(f));
        o.main_received(frame_key(f));
    }
    host_transfer(o, g);
    o.main_received(frame_key(g));
    o.finish();
    EXPECT_EQ(o.counts(H).retries, 3u);
    EXPECT_EQ(o.counts(H).abandoned, 1u);
    EXPECT_EQ(o.commands().matched, 1u);
    // Executed four times, the host told never: one frame nothing sent, and three copies of it.
    EXPECT_EQ(o.commands().unexpected, 1u);
    EXPECT_EQ(o.commands().duplicates, 3u);
    EXPECT_EQ(o.commands().mismatches(), 4u);
}

TEST(LineObserver, AResponseReachingTheHostIntactIsDelivered) {
    LineObserver o;
    const proto::Frame r{"EC", 0, "ANSWER"};
    o.main_handed(frame_key(r));
    controller_transfer(o, r);
    o.finish();
    EXPECT_EQ(o.counts(C).frames_eot, 1u);
    EXPECT_EQ(o.responses().matched, 1u);
    EXPECT_EQ(o.responses().mismatches(), 0u);
}

TEST(LineObserver, AResponseSentTwiceBecauseTheHostsEotWasLostIsADuplicate) {
    LineObserver o;
    const proto::Frame r{"EC", 0, "AGAIN"};
    o.main_handed(frame_key(r));
    send(o, C, ctl(ENQ));
    send(o, H, ctl(ACK));
    send(o, C, wire(r)); // the host got it; its EOT did not reach the controller
    controller_transfer(o, r);
    o.finish();
    EXPECT_EQ(o.counts(C).retries, 1u);
    EXPECT_EQ(o.responses().received, 2u);
    EXPECT_EQ(o.responses().duplicates, 1u);
    EXPECT_EQ(o.responses().mismatches(), 1u);
}

TEST(LineObserver, AGivenUpResponseIsDroppedWithItsReasonAndStillNotDelivered) {
    LineObserver o;
    const proto::Frame r1{"EC", 0, "ONE"}, r2{"EC", 0, "TWO"}, r3{"EC", 0, "THREE"};
    o.main_handed(frame_key(r1));
    o.main_handed(frame_key(r2));
    o.main_handed(frame_key(r3));
    controller_transfer(o, r1); // done: r2 is now the oldest in the ring
    o.response_given_up();      // 0x4p: r2 never left whole
    controller_transfer(o, r3);
    o.finish();
    EXPECT_EQ(o.responses().matched, 2u);
    EXPECT_EQ(o.responses().dropped_gave_up, 1u);
    EXPECT_EQ(o.responses().lost, 0u);
    EXPECT_EQ(o.responses().mismatches(), 1u);
}

TEST(LineObserver, OfTwoEqualResponsesTheOneGivenUpIsTheOneThatStaysUndelivered) {
    LineObserver o;
    const proto::Frame r{"EC", 0, "SAME"}; // the answer to a command delivered twice
    o.main_handed(frame_key(r));
    o.main_handed(frame_key(r));
    o.response_given_up(); // the first: 0x5p after its retries
    controller_transfer(o, r);
    o.finish();
    EXPECT_EQ(o.responses().matched, 1u);
    EXPECT_EQ(o.responses().dropped_gave_up, 1u);
    EXPECT_EQ(o.responses().lost, 0u);
}

TEST(LineObserver, APortResetDropsEveryResponseInTheRing) {
    LineObserver o;
    o.main_handed(frame_key(proto::Frame{"EC", 0, "A"}));
    o.main_handed(frame_key(proto::Frame{"EC", 0, "B"}));
    o.port_reset();
    o.finish();
    EXPECT_EQ(o.responses().dropped_port_reset, 2u);
    EXPECT_EQ(o.responses().lost, 0u);
    EXPECT_EQ(o.responses().mismatches(), 2u);
}

TEST(LineObserver, AResponseThatNeverArrivesWithoutAReasonIsLost) {
    LineObserver o;
    o.main_handed(frame_key(proto::Frame{"EC", 0, "GONE"}));
    o.finish();
    EXPECT_EQ(o.responses().lost, 1u);
    EXPECT_EQ(o.responses().mismatches(), 1u);
}

// ---- the sequence comparison alone: ids, as the observer gives them ----

namespace {
SequenceMatcher::Note at(double us) { return {"", us, {}}; }
} // namespace

TEST(SequenceMatcher, TheRecordMayLagOrLeadByTheFramesInFlight) {
    SequenceMatcher m;
    // sent 0..9, the record three behind; then 10..19 with the record one ahead.
    for (FrameId i = 0; i < 10; ++i) {
        m.sent(i);
        if (i >= 3) m.received(i - 3);
    }
    for (FrameId i = 7; i < 10; ++i) m.received(i);
    for (FrameId i = 10; i < 20; ++i) {
        m.received(i);
        m.sent(i);
    }
    m.finish();
    EXPECT_EQ(m.counts().matched, 20u);
    EXPECT_EQ(m.counts().mismatches(), 0u);
}

TEST(SequenceMatcher, ALossCountsOne) {
    SequenceMatcher m;
    for (FrameId i = 0; i < 5; ++i) m.sent(i);
    for (FrameId i : {0, 1, 3, 4}) m.received(i);
    m.finish();
    EXPECT_EQ(m.counts().lost, 1u);
    EXPECT_EQ(m.counts().mismatches(), 1u);
}

TEST(SequenceMatcher, AReorderingCountsOne) {
    for (const bool record_first : {false, true}) {
        SCOPED_TRACE(record_first ? "the record leads" : "the intention leads");
        SequenceMatcher m;
        if (!record_first)
            for (FrameId i = 0; i < 4; ++i) m.sent(i);
        for (FrameId i : {0, 2, 1, 3}) m.received(i);
        if (record_first)
            for (FrameId i = 0; i < 4; ++i) m.sent(i);
        m.finish();
        EXPECT_EQ(m.counts().reordered, 1u);
        EXPECT_EQ(m.counts().lost + m.counts().duplicates + m.counts().unexpected, 0u);
        EXPECT_EQ(m.counts().mismatches(), 1u);
    }
}

TEST(SequenceMatcher, AFrameReceivedTwiceIsOneDuplicateWhicheverRecordLeads) {
    for (const bool record_first : {true, false}) {
        SCOPED_TRACE(record_first ? "the record leads" : "the intention leads");
        SequenceMatcher m;
        if (record_first) {
            m.received(7);
            m.received(7); // the main CPU took the retry too
            m.sent(7);     // the host's EOT came with the retry
        } else {
            m.sent(7);
            m.received(7);
            m.received(7); // the host read the controller's retry as well
        }
        m.finish();
        EXPECT_EQ(m.counts().matched, 1u);
        EXPECT_EQ(m.counts().duplicates, 1u);
        EXPECT_EQ(m.counts().unexpected, 0u);
        EXPECT_EQ(m.counts().mismatches(), 1u);
    }
}

// Ten equal frames sent and eleven received: by content, any one of the eleven could be the extra.
// By id, the extra is a copy of frame 4, and the books say so.
TEST(SequenceMatcher, AmongEqualFramesTheCopyIsTheOneWithTheRepeatedId) {
    SequenceMatcher m;
    for (FrameId i = 0; i < 10; ++i) {
        m.received(i, at(double(i)));
        if (i == 4) m.received(4, at(4.5));
        m.sent(i);
    }
    m.finish();
    EXPECT_EQ(m.counts().duplicates, 1u);
    EXPECT_EQ(m.counts().mismatches(), 1u);
    ASSERT_EQ(m.unexplained().size(), 1u);
    EXPECT_EQ(m.unexplained()[0].time_us, 4.5);
}

TEST(SequenceMatcher, AFrameNothingMadeIsUnexpectedAndItsCopiesDuplicates) {
    SequenceMatcher m;
    m.received(kNoFrameId);
    m.received(5); // never sent: unexpected at the end ...
    m.received(5); // ... and this a copy of it
    m.finish();
    EXPECT_EQ(m.counts().unexpected, 2u);
    EXPECT_EQ(m.counts().duplicates, 1u);
    EXPECT_EQ(m.counts().mismatches(), 3u);
}

TEST(SequenceMatcher, ACopyIsListedWithWhatHitItsTransfer) {
    SequenceMatcher m;
    m.sent(1);
    m.received(1);
    m.blame(1, {"injected fault: a host character dropped", 3}); // the host's EOT
    m.received(1, at(9));
    m.finish();
    EXPECT_EQ(m.counts().duplicates, 1u);
    EXPECT_EQ(m.counts().after_fault, 1u);
    EXPECT_EQ(m.counts().expected, 0u); // listed with its cause, still counted
    EXPECT_EQ(m.counts().mismatches(), 1u);
    ASSERT_EQ(m.unexplained().size(), 1u);
    EXPECT_EQ(m.unexplained()[0].cause.what, "injected fault: a host character dropped");
}

TEST(SequenceMatcher, MemoryIsBoundedWhateverIsLostOrUnexpected) {
    SequenceMatcher m;
    for (FrameId i = 0; i < 10000; ++i) {
        m.sent(2 * i);
        m.received(2 * i + 1);
        EXPECT_LE(m.waiting(), 2 * SequenceMatcher::kWindow);
    }
    m.finish();
    EXPECT_EQ(m.waiting(), 0u);
    EXPECT_EQ(m.counts().lost, 10000u);
    EXPECT_EQ(m.counts().unexpected, 10000u);
}

TEST(SequenceMatcher, ExplainedLossesAreCountedApartAndOnlyForWaitingFrames) {
    SequenceMatcher m;
    m.sent(1);
    m.sent(2);
    m.received(2);
    EXPECT_TRUE(m.explain(1, DropReason::port_reset));
    EXPECT_FALSE(m.explain(2, DropReason::gave_up)); // matched: nothing to explain
    m.finish();
    EXPECT_EQ(m.counts().dropped_port_reset, 1u);
    EXPECT_EQ(m.counts().lost, 0u);
    EXPECT_EQ(m.counts().mismatches(), 1u);
}

TEST(FrameKey, EqualFramesEqualKeysAndAnyFieldChangesIt) {
    const FrameKey k = frame_key("EC", 0, "HELLO");
    EXPECT_EQ(k, frame_key(proto::Frame{"EC", 0, "HELLO"}));
    EXPECT_NE(k, frame_key("ED", 0, "HELLO"));
    EXPECT_NE(k, frame_key("EC", 1, "HELLO"));
    EXPECT_NE(k, frame_key("EC", 0, "HELLP"));
    EXPECT_EQ(k.size, 5u);
}
