// rcsim — an independent observer of one serial port: a passive protocol decoder on the line and
// the exactly-once comparison of what the line carried with the main CPU's own DP-RAM side
// (docs/scenarios.md "How each figure is measured").
//
// The decoder sees every character exactly as its receiver decoded it (SerialLine::on_deliver:
// the receiver's format, its parity and framing errors), in both directions, whatever host is
// attached. It recognises ENQ, ACK, NAK, EOT and whole frames SOH..ETX (models/frame_codec.h) and
// counts per direction: ENQs, frames offered, frames that arrived bad, frames acknowledged with
// EOT, NAKs, retries and frames abandoned. It needs no cooperation from the host, the firmware or
// the main CPU.
//
// Two sequence comparisons per port, each between an intention and a record:
//   commands:  the host frames whose EOT reached the host (what the host was told was delivered)
//              against the valid frames the main CPU reassembled from DP-RAM;
//   responses: the frames the main CPU handed to DP-RAM (every chunk acknowledged) against the
//              controller frames that reached the host intact.
// A swallowed EOT makes the host send a frame the controller already accepted (the protocol has
// no sequence numbers): the main CPU then holds it twice, and that is a duplicate.
//
// Expected drops (docs/scenarios.md "Expected drops"): a frame that did not arrive because of
// something the scenario did to its port — a BREAK from the host, an injected fault or noise on a
// character of its line — is counted apart and does not count against the exactly-once checks.
// The world tells the observer what it did (line_fault) and the observer sees every BREAK and
// port reset; the rule that ties a drop to a cause is LineObserver's (below). A run a signal
// stopped leaves the frames still on their way "in flight", neither delivered nor lost.
//
// Plain C++ (no SystemC): the world feeds it (scenarios/world/world.h).
#pragma once

#include "models/frame_codec.h"

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace rcsim {

/// A frame's identity: a 64-bit FNV-1a hash of token, BCH and data, and the data length. Two
/// different frames compare equal with probability about 2^-64 per comparison (under 1e-12
/// for the ~10^7 comparisons of the longest run a scenario allows).
struct FrameKey {
    std::uint64_t hash = 0;
    std::uint32_t size = 0;
    bool operator==(const FrameKey& o) const { return hash == o.hash && size == o.size; }
    bool operator!=(const FrameKey& o) const { return !(*this == o); }
};
FrameKey frame_key(const std::string& token, std::uint8_t bch, const std::string& data);
inline FrameKey frame_key(const proto::Frame& f) { return frame_key(f.token, f.bch, f.data); }

/// Why a frame that was sent did not arrive, when something reported it.
enum class DropReason : std::uint8_t { none, gave_up, port_reset };

/// Something the scenario did to a port that can keep a frame in flight there from arriving: a
/// BREAK, an injected fault or noise on a character of its line.
struct ScenarioCause {
    std::string what;   // e.g. "BREAK from the host"; empty: none
    double time_us = 0; // simulated time, when the observer was told of it
    bool empty() const { return what.empty(); }
};

/// The retries the protocol owes a frame after its first attempt (docs/system.md §6.2: "at most 3
/// times", 4 attempts in all; a NAK and a T1 timeout each end an attempt; ENQ and frame retries
/// share the count). The spec's, on both sides: the simulated hosts' retries are not a scenario
/// setting (ProtocolHost::Timing::max_retries keeps this default), and what the firmware does
/// must not set what it owes.
constexpr unsigned kMaxRetry = 3;
/// T1 (docs/system.md §6.1): the longest a sender waits for the answer to its ENQ or its frame.
constexpr double kT1Us = 50000;

/// The attempts a sender made at one frame on the line, and how many of them a scenario cause
/// hit (docs/scenarios.md "Expected drops").
struct Attempts {
    unsigned made = 0;
    unsigned hit = 0;
    /// Every attempt the protocol allows was hit: then, and only then, a give-up is the scenario's.
    bool all_owed_hit() const { return hit >= 1 + kMaxRetry; }
    /// The retries the protocol still owed when the sender gave the frame up.
    unsigned owed_retries() const { return made >= 1 + kMaxRetry ? 0 : 1 + kMaxRetry - made; }
};

/// A short, printable name of a frame for the report: `EC 00 "HELLO" (5 bytes)`, the data cut
/// after 16 characters.
std::string frame_label(const std::string& token, std::uint8_t bch, const std::string& data);

/// One frame that was not delivered exactly once, as the report lists it.
struct FrameEvent {
    enum class Kind : std::uint8_t { lost, gave_up, port_reset, duplicate, unexpected, reordered };
    Kind kind = Kind::lost;
    std::string frame;   // frame_label()
    double time_us = 0;  // sent (lost), dropped (gave_up, port_reset), received (duplicate, unexpected), final (reordered)
    ScenarioCause cause; // an expected drop's cause, or what hit a duplicate's or unexpected frame's transfer
    std::optional<Attempts> attempts; // a frame given up: the attempts its sender made and those hit
    bool expected = false;            // an expected drop (SequenceMatcher::expected_drops)
};
const char* kind_name(FrameEvent::Kind k);

/// A frame's identity in the books: given where the frame is made (LineObserver says where) and
/// carried beside it, never in the modelled bytes, to where it is consumed. A retry of a frame
/// keeps its id; an equal frame made again gets a new one.
using FrameId = std::uint64_t;
/// A frame received that no frame made can be: its id is this.
constexpr FrameId kNoFrameId = ~FrameId{0};

/// Streaming comparison of two records of the same frames — `sent` (the intention) and `received`
/// (the record) — by the frames' identity, so two equal frames are never taken for each other.
/// They arrive interleaved, the record lagging or leading by the frames in flight. Memory is
/// bounded: at most kWindow frames wait on each side, and the last kWindow matched ids are kept to
/// tell a duplicate.
///
/// Rule (docs/scenarios.md "Exactly once"): a received id that was sent and still waits matches
/// it, and the frames sent before it that still wait were overtaken: one of them received later
/// is reordered. A received id matched before is a duplicate; one never sent waits (the record
/// may lead) until kWindow more wait or finish(), then it is unexpected and its other copies are
/// duplicates. A sent frame still waiting when kWindow newer ones wait, or at finish(), is lost (or
/// dropped, with its reason). So a duplicate counts 1, a loss 1, a reordering 1.
class SequenceMatcher {
public:
    static constexpr std::size_t kWindow = 64;

    struct Counts {
        std::uint64_t sent = 0, received = 0, matched = 0;
        std::uint64_t lost = 0, reordered = 0;
        std::uint64_t duplicates = 0; // received again after the frame was matched
        std::uint64_t unexpected = 0; // received, never sent (e.g. a command the host gave up on)
        std::uint64_t dropped_gave_up = 0, dropped_port_reset = 0; // lost, with a reported reason
        /// Of the lost and dropped, those with a cause the scenario made (expected drops).
        std::uint64_t expected = 0;
        /// Of the duplicates and unexpected, those whose transfer a cause the scenario made hit
        /// (e.g. a damaged EOT, so the sender repeated a frame its receiver had taken). They still
        /// count: the protocol has no sequence numbers, and exactly once is what the check asks.
        std::uint64_t after_fault = 0;
        /// Frames still on their way when a signal stopped the run (finish(true)): never final.
        std::uint64_t in_flight = 0;
        /// Every frame not delivered exactly once and in order — lost, dropped (a reason does not
        /// make it delivered), duplicated or reordered — less the expected drops: the
        /// exactly-once check's figure.
        std::uint64_t mismatches() const {
            return lost + dropped_gave_up + dropped_port_reset - expected + duplicates + unexpected + reordered;
        }
    };

    /// What the report shows of a frame: its label, when this side had it, and a cause the
    /// scenario made while it was on its way.
    struct Note {
        std::string label;
        double time_us = 0;
        ScenarioCause cause;
        /// A sent frame's: what explains its loss, when not `cause` (a command: the cause of the
        /// attempt that got the EOT, where `cause` is its whole transfer's, for a copy).
        std::optional<ScenarioCause> loss_cause = std::nullopt;
    };
    /// The first frames the report lists of each kind.
    static constexpr std::size_t kListed = 8;

    void sent(FrameId id, Note note);
    void sent(FrameId id) { sent(id, Note()); }
    /// `id` kNoFrameId: a frame nothing made, unexpected at once.
    void received(FrameId id, Note note);
    void received(FrameId id) { received(id, Note()); }
    /// Gives sent frame `id` a reason, should it turn out lost, and the time it was dropped.
    /// `attempts` (a give-up): what its sender made of the attempts it owed; the drop is expected
    /// only when every one of them was hit (Attempts::all_owed_hit), whatever its cause.
    /// False: it is no longer waiting (matched, or final).
    bool explain(FrameId id, DropReason why, double time_us = 0, std::optional<Attempts> attempts = std::nullopt);
    /// Gives frame `id` a cause, unless it has one (`replace`: whatever it had): a waiting sent
    /// frame's, should it be lost, or a matched one's, should a copy of it arrive. False: it is
    /// no longer waiting.
    bool blame(FrameId id, const ScenarioCause& cause, bool replace = false);
    /// Makes every waiting frame final. `interrupted` (a signal stopped the run): the frames
    /// still on their way — waiting and not yet overtaken by a later one, nor dropped with a
    /// reason — are counted in_flight instead.
    void finish(bool interrupted = false);
    const Counts& counts() const { return counts_; }
    /// The first kListed expected drops, and the first kListed frames that count against the
    /// check (lost or dropped without a cause, duplicates, unexpected, reordered), in the order
    /// they became final.
    const std::vector<FrameEvent>& expected_drops() const { return expected_; }
    const std::vector<FrameEvent>& unexplained() const { return unexplained_; }
    /// Frames waiting on either side (for tests of the bound).
    std::size_t waiting() const { return waiting_.size() + early_.size(); }

private:
    /// How a sent frame was dropped, if it was.
    struct Drop {
        DropReason why = DropReason::none;
        double time_us = 0;
        ScenarioCause cause;
        std::optional<Attempts> attempts;
    };
    struct Item {
        FrameId id;
        Note note;
        Drop drop;
        bool overtaken = false; // a frame sent after it was received first
    };
    struct Matched {
        FrameId id;
        ScenarioCause cause; // what hit its transfer: the cause of a copy
    };
    std::deque<Item> waiting_;   // sent, not yet received: in the order sent
    std::deque<Item> early_;     // received, not (yet) sent: in the order received
    std::deque<Matched> recent_; // the last kWindow ids matched or found unexpected
    Counts counts_;
    std::vector<FrameEvent> expected_, unexplained_;

    void matched(FrameId id, ScenarioCause cause);
    /// Keeps `id` among the last kWindow ids seen whole (matched or unexpected), to tell a copy.
    void remember(FrameId id, ScenarioCause cause);
    Matched* recent(FrameId id);
    void lost(const Item& it);
    void copy(const Note& note, const ScenarioCause& cause);
    void never_sent(const Item& it);
    static void list(std::vector<FrameEvent>& v, FrameEvent e);
};

/// The passive decoder of one port and its two comparisons.
///
/// Which drops are expected (docs/scenarios.md "Expected drops"): a cause is something the
/// scenario did to this port — a BREAK from the host (every host is the scenario's), a BREAK the
/// scenario injected from the controller's side, a character of this line, either direction,
/// dropped or altered by an injected fault or by noise — and it explains
///   - a response dropped by the comm CPU's port reset (0x3p) that followed a BREAK from the host
///     on this port: the first such reset within kBreakResetUs of the BREAK; every response in
///     the ring goes with it. A reset with no BREAK before it (the chunk-ACK timeout, a reset the
///     main CPU asked for) explains nothing;
///   - a response given up (0x4p, 0x5p) when a cause hit every attempt the protocol allows: the
///     first and kMaxRetry retries (below). A firmware that gives up sooner, or after an attempt
///     nothing hit, is at fault, and the give-up counts with its attempts, hits and the retries
///     still owed;
///   - a response lost (never given up) when a cause hit this port while that response was the
///     oldest in the comm CPU's transmit ring (the one it was sending);
///   - a command the host got EOT for and the main CPU never received, when a cause hit this port
///     during the attempt that got the EOT (from the host's ENQ that began it): a fault can make
///     the host read an EOT the controller never sent. A cause on an earlier attempt, or a BREAK
///     or reset after the EOT, explains nothing: an EOT is a promise of delivery (docs/system.md
///     §5.2).
///
/// Attempts (docs/system.md §6.2): each begins with its sender's ENQ and lasts until the other
/// side's NAK or EOT, or T1 (plus kAttemptSlackUs) after the sender's last character or the ACK
/// it got. A cause hits the attempts live at its time, either direction's. An ENQ the cause itself
/// destroyed is an attempt the receiver never saw: a dropped character's byte is known (the line
/// kept its bits), and a dropped ENQ begins a hit attempt; an altered one whose byte is lost begins
/// one when neither side has a live attempt it could belong to (the controller only with a
/// response to send).
/// Duplicates, unexpected and reordered frames are never expected: exactly once is what the
/// check asks, whatever made the sender repeat itself. A duplicate or unexpected frame whose
/// transfer a cause hit is listed with that cause (Counts::after_fault).
///
/// Frame identity (issue 33 item 7): the books match ids (FrameId), not contents. A command's id
/// is made when the host offers it on the line, valid as the controller's receiver decoded it; a
/// retry of it in the same transfer (no EOT reached the host in between) keeps the id. The comm
/// CPU forwards the frames it took in the order it took them, so a frame the main CPU reassembles
/// is the oldest offered one equal to it (frames offered before it that never arrive were refused
/// or given up, and leave with it). A response's id is made when the main CPU hands it to DP-RAM;
/// the comm CPU sends its ring in order and repeats the oldest until its EOT, so a response that
/// reaches the host is the oldest in the ring equal to it. Contents only confirm the match.
class LineObserver {
public:
    enum Dir : unsigned { host_to_controller = 0, controller_to_host = 1 };
    /// The longest a BREAK from the host explains the port reset that follows it: the firmware
    /// defers a reset until an EOT'd frame is handed over, at most its 1 s chunk-ACK timeout.
    static constexpr double kBreakResetUs = 2e6;
    /// How long past T1 an attempt still takes a cause: the timers count whole 1 ms ticks from the
    /// transmitter going idle, and an answer's START may come that late (docs/system.md §6.1).
    static constexpr double kAttemptSlackUs = 2000;

    struct DirCounts {
        std::uint64_t enqs = 0;
        std::uint64_t frames_offered = 0; // SOH..ETX complete on the line
        std::uint64_t frames_bad = 0;     // of those, not a valid frame as received (checksum, line error, ...)
        std::uint64_t frames_eot = 0;     // valid frames the other side answered with EOT
        std::uint64_t naks = 0;           // NAKs the other side answered this side's ENQ or frame with
        std::uint64_t retries = 0;        // frames offered again after an attempt without EOT
        std::uint64_t abandoned = 0;      // valid frames never acknowledged: a different one followed, or the run ended
    };

    /// Simulated time in microseconds, for the times in the report; the world sets it. Unset: 0.
    std::function<double()> clock;

    // ---- the line (from SerialLine::on_deliver) ----
    /// A character as its receiver decoded it; `error`: parity or framing error.
    void line_char(Dir d, std::uint8_t byte, bool error);
    /// The receiver saw a BREAK begin: a frame in progress from that side is cut. A BREAK from
    /// the host is a cause, and explains the port reset that follows it.
    void line_break(Dir d);
    /// The character a cause hit, when it hit one: who sent it and, when the line kept its data
    /// bits (a dropped character), its byte (the low 7 bits: the control bytes are ASCII).
    struct HitChar {
        Dir from;
        std::optional<std::uint8_t> byte;
    };
    /// The scenario did something to this port's line (an injected fault, noise, a BREAK it
    /// injected): a cause for the frames on their way and the attempts live (the class comment
    /// says which); `hit` the character it destroyed, if one.
    void line_fault(const ScenarioCause& c, std::optional<HitChar> hit = std::nullopt);
    /// The attempts of the frame direction d's sender is on (none between transfers).
    const Attempts& attempts(Dir d) const { return dir_[d].attempts; }

    // ---- the main CPU's DP-RAM side ----
    void main_received(const FrameKey& k, std::string label = {});
    /// A response the main CPU handed to DP-RAM (every chunk acknowledged by the comm CPU).
    void main_handed(const FrameKey& k, std::string label = {});
    /// The comm CPU gave up on the response it was sending (mailbox word 0x4p or 0x5p).
    void response_given_up();
    /// The port was reset (0x3p): the comm CPU's transmit ring, and every response in it, is
    /// dropped, and a response frame on the line is cut there. `by_main_cpu`: a reset the main CPU
    /// asked for (never explained by a BREAK).
    void port_reset(bool by_main_cpu = false);

    /// End of the run: frames still unanswered are abandoned, unmatched ones final.
    /// `interrupted` (a signal stopped the run): those still on their way are in flight instead.
    void finish(bool interrupted = false);

    /// Responses handed to DP-RAM that the comm CPU has neither had EOT for nor dropped yet.
    std::size_t responses_in_flight() const { return in_ring_.size(); }
    const DirCounts& counts(Dir d) const { return dir_[d].counts; }

    /// Where the sender of direction d stands in the protocol (trace counters; the values are
    /// the counter's, docs/tools.md "Perfetto trace").
    enum class SenderState : std::uint8_t { idle = 0, enq_sent = 1, frame_on_line = 2, awaiting_eot = 3 };
    SenderState state(Dir d) const;
    /// Called when a frame from direction d is complete on the line (valid or not; `frame` is
    /// the decoded frame when valid); empty (no cost) by default.
    std::function<void(Dir d, bool valid, const proto::Frame& frame)> on_frame;
    std::uint64_t enq_collisions() const { return enq_collisions_; }
    std::uint64_t breaks() const { return breaks_; }
    const SequenceMatcher::Counts& commands() const { return commands_.counts(); }
    const SequenceMatcher::Counts& responses() const { return responses_.counts(); }
    /// The comparisons themselves, for the frames the report lists.
    const SequenceMatcher& command_books() const { return commands_; }
    const SequenceMatcher& response_books() const { return responses_; }

private:
    enum class Await : std::uint8_t { none, enq, frame };
    struct Sender {
        proto::FrameDecoder decoder;
        bool collecting = false;
        Await await = Await::none;
        bool open = false;             // the last frame offered got no EOT yet
        bool last_good = false;        // ... and it was valid as received
        std::optional<FrameKey> last;  // the last valid frame offered without EOT
        std::string last_label;        // ... its frame_label()
        FrameId transfer = kNoFrameId; // ... its id: a retry keeps it
        ScenarioCause cause;           // the first cause since this sender's transfer began
        ScenarioCause attempt_cause;   // the first cause that hit its current attempt
        DirCounts counts;
        Attempts attempts;             // of the current transfer
        bool attempt_hit = false;      // the current attempt was hit
        double attempt_until = -1;     // ... and takes causes until then (us)
        /// The transfer is over (its EOT, a give-up, a port reset): nothing offered waits for an
        /// answer, and the next ENQ begins a new count of attempts.
        void end_transfer() {
            open = false;
            last.reset();
            cause = {};
            attempt_cause = {};
            await = Await::none;
            end_attempts();
        }
        void end_attempts() {
            attempts = {};
            attempt_hit = false;
            attempt_until = -1;
        }
        bool attempt_live(double t) const { return attempts.made > 0 && t <= attempt_until; }
    };
    std::array<Sender, 2> dir_;
    std::uint64_t enq_collisions_ = 0, breaks_ = 0;
    SequenceMatcher commands_, responses_;
    FrameId next_id_ = 0;
    /// A frame and its id, where the observer follows it between its making and its consumer.
    struct Carried {
        FrameId id;
        FrameKey key;
        ScenarioCause cause; // commands: the first cause that hit its transfer
    };
    // Valid commands offered on the line and not yet found at the main CPU, oldest first; and the
    // last kWindow found there, to name a copy forwarded again.
    std::deque<Carried> offered_, forwarded_;
    // Responses in the comm CPU's transmit ring, oldest first (it sends and gives up in order);
    // and the last kWindow it had EOT for, to name a copy sent again.
    std::deque<Carried> in_ring_, sent_;
    // The last BREAK from the host not yet followed by a port reset of the comm CPU.
    ScenarioCause break_before_reset_;

    double now() const { return clock ? clock() : 0.0; }
    void begin_attempt(Dir d, double t);
    /// Sender d's attempt takes causes until T1 after now (its last character, or the ACK it got).
    void extend_attempt(Dir d) { dir_[d].attempt_until = now() + kT1Us + kAttemptSlackUs; }
    void hit_attempts(double t);
    bool destroyed_enq(const HitChar& h, double t) const;
    void control(Dir d, std::uint8_t byte);
    void frame_done(Dir d, bool good);
    void acknowledged(Dir d);
    FrameId command_id(const FrameKey& k, ScenarioCause& cause);
    FrameId response_id(const FrameKey& k) const;
    static void keep_last(std::deque<Carried>& q, Carried c);
};

} // namespace rcsim
