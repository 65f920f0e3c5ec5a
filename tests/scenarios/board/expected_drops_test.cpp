// Expected drops and frames in flight (docs/scenarios.md "Expected drops", "Interrupted runs"):
// which drops a cause the scenario made explains, and which it does not, fed byte by byte as in
// line_observer_test.cpp, with a clock the test moves by hand.
#include "scenarios/board/line_observer.h"

#include <gtest/gtest.h>

#include <string>

using namespace rcsim;
using proto::ACK;
using proto::ENQ;
using proto::EOT;

namespace {

constexpr auto H = LineObserver::host_to_controller;
constexpr auto C = LineObserver::controller_to_host;

std::string wire(const proto::Frame& f) { return proto::encode(f); }
std::string ctl(std::uint8_t b) { return std::string(1, static_cast<char>(b)); }

void send(LineObserver& o, LineObserver::Dir d, const std::string& bytes) {
    for (unsigned char b : bytes) o.line_char(d, b, false);
}

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

/// An observer whose clock reads `now` (microseconds).
struct Clocked {
    LineObserver o;
    double now = 0;
    Clocked() { o.clock = [this] { return now; }; }
};

proto::Frame resp(const std::string& data) { return proto::Frame{"EC", 0, data}; }
void hand(LineObserver& o, const proto::Frame& f) {
    o.main_handed(frame_key(f), frame_label(f.token, f.bch, f.data));
}

} // namespace

TEST(ExpectedDrops, APortResetAfterAHostBreakDropsTheRingAsExpected) {
    Clocked c;
    hand(c.o, resp("ONE"));
    hand(c.o, resp("TWO"));
    c.now = 1000;
    c.o.line_break(H); // the controller's receiver detects the host's BREAK ...
    c.now = 2500;
    c.o.port_reset(); // ... and the comm CPU resets the port (0x3p)
    c.o.finish();
    const auto& r = c.o.responses();
    EXPECT_EQ(r.dropped_port_reset, 2u);
    EXPECT_EQ(r.expected, 2u);
    EXPECT_EQ(r.mismatches(), 0u);
    const auto& e = c.o.response_books().expected_drops();
    ASSERT_EQ(e.size(), 2u);
    EXPECT_EQ(e[0].kind, FrameEvent::Kind::port_reset);
    EXPECT_EQ(e[0].frame, "EC 00 \"ONE\" (3 bytes)");
    EXPECT_EQ(e[0].time_us, 2500);
    EXPECT_EQ(e[0].cause.what, "port reset after a BREAK from the host");
    EXPECT_EQ(e[0].cause.time_us, 1000);
    EXPECT_TRUE(c.o.response_books().unexplained().empty());
}

TEST(ExpectedDrops, AResetWithoutABreakBeforeItStillCounts) {
    Clocked c;
    hand(c.o, resp("ONE"));
    c.o.port_reset(); // the chunk-ACK timeout, say: nothing the scenario did
    c.o.finish();
    EXPECT_EQ(c.o.responses().expected, 0u);
    EXPECT_EQ(c.o.responses().mismatches(), 1u);
    ASSERT_EQ(c.o.response_books().unexplained().size(), 1u);
    EXPECT_EQ(c.o.response_books().unexplained()[0].kind, FrameEvent::Kind::port_reset);
}

TEST(ExpectedDrops, ABreakExplainsOnlyTheFirstCommCpuResetAndOnlyWithinItsWindow) {
    Clocked c;
    c.o.line_break(H);
    hand(c.o, resp("BY-MAIN"));
    c.now = 10;
    c.o.port_reset(true); // the main CPU's own reset (its ACK timeout) is never the BREAK's
    hand(c.o, resp("FIRST"));
    c.now = 20;
    c.o.port_reset(); // the BREAK's reset
    hand(c.o, resp("SECOND"));
    c.now = 30;
    c.o.port_reset(); // a second reset: the BREAK was used up
    c.o.line_break(H);
    hand(c.o, resp("LATE"));
    c.now = 30 + LineObserver::kBreakResetUs + 1;
    c.o.port_reset(); // too long after the BREAK
    c.o.finish();
    EXPECT_EQ(c.o.responses().dropped_port_reset, 4u);
    EXPECT_EQ(c.o.responses().expected, 1u);
    EXPECT_EQ(c.o.responses().mismatches(), 3u);
    ASSERT_EQ(c.o.response_books().expected_drops().size(), 1u);
    EXPECT_EQ(c.o.response_books().expected_drops()[0].frame, "EC 00 \"FIRST\" (5 bytes)");
}

// ---- retries owed (docs/system.md §6.2: the first attempt and kMaxRetry = 3 retries) ----

// The comm CPU's attempt whose ENQ a fault dropped: the host never saw it, T1 runs out. `t` in us.
void dropped_controller_enq(Clocked& c, double t) {
    c.now = t;
    c.o.line_fault({"injected fault: a controller character dropped", t}, LineObserver::HitChar{C, ENQ});
}

// T1 and the back-off of retry n after an attempt that began at t (docs/system.md §6.1).
double retry_at(double t, unsigned n) { return t + kT1Us + 10000.0 * n; }

TEST(RetriesOwed, TheProtocolOwesTheFirstAttemptAndThreeRetries) {
    EXPECT_EQ(kMaxRetry, 3u); // docs/system.md §6.2: "at most 3 times (4 attempts in all)"
    EXPECT_EQ((Attempts{1, 1}).owed_retries(), 3u);
    EXPECT_EQ((Attempts{4, 3}).owed_retries(), 0u);
    EXPECT_FALSE((Attempts{3, 3}).all_owed_hit());
    EXPECT_TRUE((Attempts{4, 4}).all_owed_hit());
}

TEST(RetriesOwed, AGiveUpAfterEveryOwedAttemptWasHitIsExpected) {
    Clocked c;
    hand(c.o, resp("SENDING"));
    double t = 700;
    for (unsigned n = 1; n <= 4; ++n) {
        dropped_controller_enq(c, t);
        t = retry_at(t, n);
    }
    c.now = t;
    c.o.response_given_up(); // 0x4p after the third retry
    c.o.finish();
    const auto& r = c.o.responses();
    EXPECT_EQ(r.dropped_gave_up, 1u);
    EXPECT_EQ(r.expected, 1u);
    EXPECT_EQ(r.mismatches(), 0u);
    const auto& e = c.o.response_books().expected_drops();
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(e[0].frame, "EC 00 \"SENDING\" (7 bytes)");
    EXPECT_EQ(e[0].kind, FrameEvent::Kind::gave_up);
    EXPECT_EQ(e[0].time_us, t);
    EXPECT_EQ(e[0].cause.time_us, 700);
    ASSERT_TRUE(e[0].attempts);
    EXPECT_EQ(e[0].attempts->made, 4u);
    EXPECT_EQ(e[0].attempts->hit, 4u);
    EXPECT_TRUE(c.o.response_books().unexplained().empty());
}

// The firmware with MAX_RETRY patched to 0: one dropped ENQ, and it gives the response up.
TEST(RetriesOwed, AGiveUpWithRetriesStillOwedCounts) {
    Clocked c;
    hand(c.o, resp("SENDING"));
    hand(c.o, resp("WAITING"));
    dropped_controller_enq(c, 700);
    c.now = retry_at(700, 1);
    c.o.response_given_up();
    // The next response's transfer starts a count of its own, and goes through.
    c.now += 1000;
    controller_transfer(c.o, resp("WAITING"));
    c.o.finish();
    const auto& r = c.o.responses();
    EXPECT_EQ(r.dropped_gave_up, 1u);
    EXPECT_EQ(r.expected, 0u);
    EXPECT_EQ(r.mismatches(), 1u);
    ASSERT_EQ(c.o.response_books().unexplained().size(), 1u);
    const FrameEvent& e = c.o.response_books().unexplained()[0];
    EXPECT_EQ(e.kind, FrameEvent::Kind::gave_up);
    EXPECT_FALSE(e.expected);
    EXPECT_EQ(e.time_us, retry_at(700, 1));
    EXPECT_EQ(e.cause.what, "injected fault: a controller character dropped"); // it was hit, still it counts
    ASSERT_TRUE(e.attempts);
    EXPECT_EQ(e.attempts->made, 1u);
    EXPECT_EQ(e.attempts->hit, 1u);
    EXPECT_EQ(e.attempts->owed_retries(), 3u);
    EXPECT_EQ(c.o.attempts(C).made, 0u); // the delivered one's transfer is over
}

// Four attempts, the first hit; the host answers none of the other three (nothing the scenario
// did): the give-up counts, though the firmware owed nothing more.
TEST(RetriesOwed, AGiveUpAfterAnAttemptNoCauseHitCounts) {
    Clocked c;
    hand(c.o, resp("SENDING"));
    dropped_controller_enq(c, 700);
    double t = retry_at(700, 1);
    for (unsigned n = 2; n <= 4; ++n) {
        c.now = t;
        send(c.o, C, ctl(ENQ)); // seen by the host, never answered
        t = retry_at(t, n);
    }
    EXPECT_EQ(c.o.attempts(C).made, 4u);
    EXPECT_EQ(c.o.attempts(C).hit, 1u);
    c.now = t;
    c.o.response_given_up();
    c.o.finish();
    EXPECT_EQ(c.o.responses().expected, 0u);
    EXPECT_EQ(c.o.responses().mismatches(), 1u);
    ASSERT_EQ(c.o.response_books().unexplained().size(), 1u);
    const FrameEvent& e = c.o.response_books().unexplained()[0];
    ASSERT_TRUE(e.attempts);
    EXPECT_EQ(e.attempts->made, 4u);
    EXPECT_EQ(e.attempts->hit, 1u);
    EXPECT_EQ(e.attempts->owed_retries(), 0u);
}

// A cause in the back-off between two attempts hits neither: the attempt before ended at its NAK.
TEST(RetriesOwed, ACauseAfterTheNakHitsNoAttempt) {
    Clocked c;
    hand(c.o, resp("SENDING"));
    c.now = 100;
    send(c.o, C, ctl(ENQ));
    send(c.o, H, ctl(proto::NAK));
    c.now = 5000; // back-off: no attempt of either side live, and the byte is known (not an ENQ)
    c.o.line_fault({"injected fault: a host character dropped", 5000}, LineObserver::HitChar{H, ACK});
    EXPECT_EQ(c.o.attempts(C).made, 1u);
    EXPECT_EQ(c.o.attempts(C).hit, 0u);
    EXPECT_EQ(c.o.attempts(H).made, 0u);
}

// An altered character whose byte is lost: an ENQ when nothing else could have been on the line
// (the controller with a response to send), an answer to a live attempt otherwise.
TEST(RetriesOwed, AnAlteredCharacterBeginsAnAttemptOnlyWhenNoneIsLive) {
    Clocked c;
    hand(c.o, resp("SENDING"));
    c.now = 100;
    c.o.line_fault({"noise on a controller character", 100}, LineObserver::HitChar{C, std::nullopt});
    EXPECT_EQ(c.o.attempts(C).made, 1u);
    EXPECT_EQ(c.o.attempts(C).hit, 1u);
    c.now = 200; // the host's ENQ of its own attempt, then the controller's answer is altered
    send(c.o, H, ctl(ENQ));
    c.o.line_fault({"noise on a controller character", 300}, LineObserver::HitChar{C, std::nullopt});
    EXPECT_EQ(c.o.attempts(C).made, 1u); // not a new attempt: the ACK the host waits for
    EXPECT_EQ(c.o.attempts(H).made, 1u);
    EXPECT_EQ(c.o.attempts(H).hit, 1u);
}

// The host's side: its ENQs dropped by a fault are attempts the controller never saw, each hit.
TEST(RetriesOwed, TheHostsDroppedEnqsAreHitAttempts) {
    Clocked c;
    double t = 100;
    for (unsigned n = 1; n <= 4; ++n) {
        c.now = t;
        c.o.line_fault({"injected fault: a host character dropped", t}, LineObserver::HitChar{H, ENQ});
        t = retry_at(t, n);
    }
    EXPECT_EQ(c.o.attempts(H).made, 4u);
    EXPECT_EQ(c.o.attempts(H).hit, 4u);
    EXPECT_TRUE(c.o.attempts(H).all_owed_hit());
    EXPECT_EQ(c.o.attempts(C).made, 0u);
}

// The host's side: a command the controller EOT'd on a retry and the main CPU never received.
// The cause hit the first attempt (NAKed), not the one that got the EOT: it explains nothing.
TEST(RetriesOwed, ACauseOnAnEarlierAttemptExplainsNoLostCommand) {
    Clocked c;
    const proto::Frame f = resp("RETRIED"), g = resp("NEXT");
    send(c.o, H, ctl(ENQ));
    send(c.o, C, ctl(ACK));
    c.o.line_fault({"injected fault: a host character altered", 0}, LineObserver::HitChar{H, std::nullopt});
    send(c.o, H, wire(f));
    send(c.o, C, ctl(proto::NAK));
    c.now = retry_at(0, 1);
    send(c.o, H, ctl(ENQ));
    send(c.o, C, ctl(ACK));
    send(c.o, H, wire(f));
    EXPECT_EQ(c.o.attempts(H).made, 2u);
    EXPECT_EQ(c.o.attempts(H).hit, 1u);
    send(c.o, C, ctl(EOT));
    host_transfer(c.o, g);
    c.o.main_received(frame_key(g));
    c.o.finish();
    EXPECT_EQ(c.o.commands().lost, 1u);
    EXPECT_EQ(c.o.commands().expected, 0u);
    EXPECT_EQ(c.o.commands().mismatches(), 1u);
}

TEST(ExpectedDrops, ACommandHitDuringItsTransferAndNeverReceivedIsExpected) {
    Clocked c;
    const proto::Frame f = resp("HIT"), g = resp("NEXT");
    send(c.o, H, ctl(ENQ));
    send(c.o, C, ctl(ACK));
    c.o.line_fault({"noise on a controller character", 5});
    send(c.o, H, wire(f));
    send(c.o, C, ctl(EOT)); // e.g. the controller's NAK, read as EOT by the host
    host_transfer(c.o, g);
    c.o.main_received(frame_key(g));
    c.o.finish();
    EXPECT_EQ(c.o.commands().lost, 1u);
    EXPECT_EQ(c.o.commands().expected, 1u);
    EXPECT_EQ(c.o.commands().mismatches(), 0u);
    ASSERT_EQ(c.o.command_books().expected_drops().size(), 1u);
    EXPECT_EQ(c.o.command_books().expected_drops()[0].cause.what, "noise on a controller character");
}

TEST(ExpectedDrops, ABreakOrResetAfterTheEotExplainsNoLostCommand) {
    Clocked c;
    const proto::Frame f = resp("PROMISED"), g = resp("NEXT");
    host_transfer(c.o, f); // EOT: a promise of delivery
    c.o.line_break(H);
    c.o.port_reset();
    c.o.line_fault({"injected fault: a host character altered", 1});
    host_transfer(c.o, g);
    c.o.main_received(frame_key(g));
    c.o.finish();
    EXPECT_EQ(c.o.commands().lost, 1u);
    EXPECT_EQ(c.o.commands().expected, 0u);
    EXPECT_EQ(c.o.commands().mismatches(), 1u);
}

TEST(ExpectedDrops, AFaultBeforeAFreshTransferIsNotItsCause) {
    Clocked c;
    const proto::Frame f = resp("CLEAN"), g = resp("NEXT");
    c.o.line_fault({"noise on a host character", 1}); // the host is idle
    host_transfer(c.o, f);
    host_transfer(c.o, g);
    c.o.main_received(frame_key(g));
    c.o.finish();
    EXPECT_EQ(c.o.commands().expected, 0u);
    EXPECT_EQ(c.o.commands().mismatches(), 1u);
}

TEST(ExpectedDrops, DuplicatesAreNeverExpected) {
    Clocked c;
    const proto::Frame r = resp("AGAIN");
    hand(c.o, r);
    send(c.o, C, ctl(ENQ));
    send(c.o, H, ctl(ACK));
    c.o.line_fault({"injected fault: a host character dropped", 3}); // the host's EOT
    send(c.o, C, wire(r));
    controller_transfer(c.o, r);
    c.o.finish();
    EXPECT_EQ(c.o.responses().duplicates, 1u);
    EXPECT_EQ(c.o.responses().expected, 0u);
    EXPECT_EQ(c.o.responses().mismatches(), 1u);
    ASSERT_EQ(c.o.response_books().unexplained().size(), 1u);
    EXPECT_EQ(c.o.response_books().unexplained()[0].kind, FrameEvent::Kind::duplicate);
    // ... though it names what made the controller send it again.
    EXPECT_EQ(c.o.responses().after_fault, 1u);
    EXPECT_EQ(c.o.response_books().unexplained()[0].cause.what, "injected fault: a host character dropped");
}

// ---- frame identity (issue 33 item 7) ----

// Two equal responses in the ring. The host's EOT for the first is destroyed, so the controller
// sends the first again; then a host BREAK's port reset drops the second. By content the books saw
// two equal frames handed and two received, "2 delivered"; by identity the first arrived twice and
// the second never did.
TEST(FrameIdentity, EqualResponsesAreToldApartADuplicateAndAnExpectedDrop) {
    Clocked c;
    const proto::Frame r = resp("0");
    hand(c.o, r);
    hand(c.o, r); // the answer to an equal command, right behind it
    send(c.o, C, ctl(ENQ));
    send(c.o, H, ctl(ACK));
    send(c.o, C, wire(r));
    c.now = 10;
    c.o.line_fault({"injected fault: a host character dropped", 10}); // the host's EOT
    c.now = 20;
    controller_transfer(c.o, r); // the first again, and this time its EOT
    c.now = 30;
    c.o.line_break(H);
    c.now = 40;
    c.o.port_reset(); // the second goes with the ring
    c.o.finish();
    EXPECT_EQ(c.o.responses().matched, 1u);
    EXPECT_EQ(c.o.responses().duplicates, 1u);
    EXPECT_EQ(c.o.responses().after_fault, 1u);
    EXPECT_EQ(c.o.responses().dropped_port_reset, 1u);
    EXPECT_EQ(c.o.responses().expected, 1u);
    EXPECT_EQ(c.o.responses().lost + c.o.responses().reordered, 0u);
    EXPECT_EQ(c.o.responses().mismatches(), 1u); // the duplicate
}

// The issue's own case: of two equal responses the first is flushed by a port reset after a host
// BREAK, the second delivered after an equal frame went before it. "1 dropped (port reset) and the
// rest delivered", not "1 lost and 1 reordered".
TEST(FrameIdentity, AFlushedResponseAndAnEqualDeliveredOneAreNotConfused) {
    Clocked c;
    const proto::Frame ec = resp("0"), st{"ST", 0, "0"};
    hand(c.o, ec);
    c.now = 10;
    c.o.line_break(H);
    c.now = 20;
    c.o.port_reset(); // the first EC goes
    hand(c.o, st);
    hand(c.o, ec);
    hand(c.o, st);
    controller_transfer(c.o, st);
    controller_transfer(c.o, ec);
    controller_transfer(c.o, st);
    c.o.finish();
    EXPECT_EQ(c.o.responses().matched, 3u);
    EXPECT_EQ(c.o.responses().dropped_port_reset, 1u);
    EXPECT_EQ(c.o.responses().expected, 1u);
    EXPECT_EQ(c.o.responses().lost + c.o.responses().reordered + c.o.responses().duplicates, 0u);
    EXPECT_EQ(c.o.responses().mismatches(), 0u);
}

// A command equal to one delivered before, whose every EOT a fault destroyed so the host gave it
// up, reached the main CPU anyway: by content a "duplicate" of the first; by identity a frame the
// host was never told of, unexpected, after that fault.
TEST(FrameIdentity, AnEqualCommandTheHostGaveUpOnIsUnexpectedNotADuplicate) {
    Clocked c;
    const proto::Frame x{"EC", 0, "X"}, y{"EC", 0, "Y"};
    host_transfer(c.o, x);
    c.o.main_received(frame_key(x));
    send(c.o, H, ctl(ENQ));
    send(c.o, C, ctl(ACK));
    send(c.o, H, wire(x)); // the same command again, a new one
    c.now = 50;
    c.o.line_fault({"injected fault: a controller character dropped", 50}); // its EOT
    c.o.main_received(frame_key(x));
    host_transfer(c.o, y); // the host gave x up and went on
    c.o.main_received(frame_key(y));
    c.o.finish();
    EXPECT_EQ(c.o.commands().matched, 2u);
    EXPECT_EQ(c.o.commands().duplicates, 0u);
    EXPECT_EQ(c.o.commands().unexpected, 1u);
    EXPECT_EQ(c.o.commands().after_fault, 1u);
    ASSERT_EQ(c.o.command_books().unexplained().size(), 1u);
    EXPECT_EQ(c.o.command_books().unexplained()[0].cause.time_us, 50);
}

// The main CPU takes both copies of a command whose EOT was destroyed before the host's retry got
// its EOT: the copy that has no EOT of its own is the duplicate, with that fault as its cause.
TEST(FrameIdentity, ARetriedCommandTakenTwiceIsADuplicateOfItsOwnTransfer) {
    Clocked c;
    const proto::Frame x{"EC", 0, "X"};
    send(c.o, H, ctl(ENQ));
    send(c.o, C, ctl(ACK));
    send(c.o, H, wire(x));
    c.o.line_fault({"noise on a controller character", 7}); // the EOT
    c.o.main_received(frame_key(x));
    host_transfer(c.o, x); // the retry: same frame, same transfer
    c.o.main_received(frame_key(x));
    c.o.finish();
    EXPECT_EQ(c.o.counts(H).retries, 1u);
    EXPECT_EQ(c.o.commands().matched, 1u);
    EXPECT_EQ(c.o.commands().duplicates, 1u);
    EXPECT_EQ(c.o.commands().after_fault, 1u);
    EXPECT_EQ(c.o.commands().unexpected, 0u);
}

TEST(ExpectedDrops, TheListsAreBoundedAndTheCountsAreNot) {
    Clocked c;
    for (int i = 0; i < 50; ++i) {
        hand(c.o, resp(std::to_string(i)));
        c.o.line_break(H);
        c.o.port_reset();
        hand(c.o, resp("x" + std::to_string(i)));
        c.o.response_given_up();
    }
    c.o.finish();
    EXPECT_EQ(c.o.responses().expected, 50u);
    EXPECT_EQ(c.o.responses().mismatches(), 50u);
    EXPECT_EQ(c.o.response_books().expected_drops().size(), SequenceMatcher::kListed);
    EXPECT_EQ(c.o.response_books().unexplained().size(), SequenceMatcher::kListed);
}

TEST(ExpectedDrops, LongDataIsCutInTheLabel) {
    EXPECT_EQ(frame_label("EC", 0x0A, std::string(40, 'x')), "EC 0A \"xxxxxxxxxxxxxxxx...\" (40 bytes)");
}

// ---- interrupted runs ----

TEST(InFlight, AnInterruptedStopLeavesWaitingFramesInFlightNotLost) {
    Clocked c;
    const proto::Frame f = resp("DONE"), g = resp("ON-ITS-WAY");
    host_transfer(c.o, f);
    c.o.main_received(frame_key(f));
    host_transfer(c.o, g); // EOT'd; the main CPU has not received it yet
    hand(c.o, resp("ANSWER")); // handed; the host has not received it yet
    const proto::Frame ahead = resp("AHEAD");
    send(c.o, H, ctl(ENQ));
    send(c.o, C, ctl(ACK));
    send(c.o, H, wire(ahead));
    c.o.main_received(frame_key(ahead)); // the record leads: its EOT is still on the line
    c.o.finish(true);
    EXPECT_EQ(c.o.commands().in_flight, 2u);
    EXPECT_EQ(c.o.commands().lost + c.o.commands().unexpected, 0u);
    EXPECT_EQ(c.o.commands().mismatches(), 0u);
    EXPECT_EQ(c.o.responses().in_flight, 1u);
    EXPECT_EQ(c.o.responses().lost, 0u);
    EXPECT_EQ(c.o.responses().mismatches(), 0u);
}

TEST(InFlight, AnInterruptedStopStillCountsWhatCompletedWrong) {
    Clocked c;
    const proto::Frame a = resp("A"), b = resp("B");
    host_transfer(c.o, a); // lost: b, sent after it, was received
    host_transfer(c.o, b);
    c.o.main_received(frame_key(b));
    hand(c.o, resp("GIVEN-UP"));
    c.o.response_given_up(); // dropped with its reason before the stop
    c.o.finish(true);
    EXPECT_EQ(c.o.commands().lost, 1u);
    EXPECT_EQ(c.o.commands().in_flight, 0u);
    EXPECT_EQ(c.o.responses().dropped_gave_up, 1u);
    EXPECT_EQ(c.o.responses().in_flight, 0u);
    EXPECT_EQ(c.o.responses().mismatches(), 1u);
}

TEST(InFlight, AnUnansweredFrameAtAnInterruptedStopIsNotAbandoned) {
    Clocked c;
    send(c.o, H, ctl(ENQ));
    send(c.o, C, ctl(ACK));
    send(c.o, H, wire(resp("NO-EOT-YET")));
    c.o.finish(true);
    EXPECT_EQ(c.o.counts(H).abandoned, 0u);
}

// Issue 33 item 6: a host's BREAK resets the port while the controller is sending a response. Its
// frame never gets its ETX: it ends at the reset, and the controller's next ACK and EOT answer the
// host's next command as on the wire, so that command counts as delivered, not "unexpected".
TEST(CutFrames, AResponseCutByAPortResetEndsThereAndTheNextTransferIsSeen) {
    Clocked c;
    hand(c.o, resp("ONE"));
    send(c.o, C, ctl(ENQ));
    send(c.o, H, ctl(ACK));
    const std::string response = wire(resp("ONE"));
    send(c.o, C, response.substr(0, 4)); // SOH and the first bytes: then the BREAK
    c.now = 1000;
    c.o.line_break(H);
    c.now = 3000;
    c.o.port_reset();
    EXPECT_EQ(c.o.state(C), LineObserver::SenderState::idle);
    c.now = 10000;
    const proto::Frame cmd{"RD", 0, "X"};
    host_transfer(c.o, cmd);
    c.o.main_received(frame_key(cmd), frame_label(cmd.token, cmd.bch, cmd.data));
    c.o.finish();
    EXPECT_EQ(c.o.counts(H).frames_eot, 1u);
    EXPECT_EQ(c.o.commands().mismatches(), 0u);
    EXPECT_EQ(c.o.commands().unexpected, 0u);
    EXPECT_EQ(c.o.counts(C).frames_offered, 0u); // cut before its ETX: never a whole frame
    EXPECT_EQ(c.o.responses().dropped_port_reset, 1u);
    EXPECT_EQ(c.o.responses().expected, 1u);
    EXPECT_EQ(c.o.responses().mismatches(), 0u);
}

// The same cut when the reset has no BREAK before it: the frame still ends at the reset (what the
// line does), and only the drop counts against the run.
TEST(CutFrames, AResponseCutByAnUnexplainedResetStillEndsThere) {
    Clocked c;
    hand(c.o, resp("ONE"));
    send(c.o, C, ctl(ENQ));
    send(c.o, H, ctl(ACK));
    send(c.o, C, wire(resp("ONE")).substr(0, 3));
    c.o.port_reset();
    const proto::Frame cmd{"RD", 0, "Y"};
    host_transfer(c.o, cmd);
    c.o.main_received(frame_key(cmd), frame_label(cmd.token, cmd.bch, cmd.data));
    c.o.finish();
    EXPECT_EQ(c.o.commands().mismatches(), 0u);
    EXPECT_EQ(c.o.responses().mismatches(), 1u);
}
