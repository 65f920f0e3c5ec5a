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
// Plain C++ (no SystemC): the world feeds it (scenarios/world/world.h).
#pragma once

#include "models/frame_codec.h"

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>

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

/// Streaming comparison of two frame sequences — `sent` (the intention) and `received` (the
/// record) — that arrive interleaved, each in its own order, the record lagging or leading by
/// the frames in flight. Memory is bounded: at most `kWindow` unmatched frames per side are
/// waiting and `kWindow` more are kept as overtaken.
///
/// Rule (docs/scenarios.md "Exactly once"): a new frame on one side matches the oldest equal
/// frame waiting on the other side; the frames older than it on either side were overtaken and
/// can only be resolved as reordered. A frame that leaves the window, or is still unmatched at
/// finish(), is final: if an equal frame of the other side is also unmatched the pair is one
/// reordering, else a sent frame is lost (or dropped, with its reason) and a received frame is a
/// duplicate (one of the last kWindow matched frames was equal to it) or unexpected. So a
/// duplicate counts 1, a loss 1, a reordering 1, and an altered frame 2 (the one that did not
/// arrive, the one that arrived instead).
class SequenceMatcher {
public:
    static constexpr std::size_t kWindow = 64;

    struct Counts {
        std::uint64_t sent = 0, received = 0, matched = 0;
        std::uint64_t lost = 0, reordered = 0;
        std::uint64_t duplicates = 0; // received again after an equal frame was matched
        std::uint64_t unexpected = 0; // received, never sent (e.g. a command the host gave up on)
        std::uint64_t dropped_gave_up = 0, dropped_port_reset = 0; // lost, with a reported reason
        /// Every frame not delivered exactly once and in order — lost, dropped (a reason does not
        /// make it delivered), duplicated or reordered: the exactly-once check's figure.
        std::uint64_t mismatches() const {
            return lost + dropped_gave_up + dropped_port_reset + duplicates + unexpected + reordered;
        }
    };

    /// Returns the frame's id, for explain().
    std::uint64_t sent(const FrameKey& k) { return add(kSent, k); }
    void received(const FrameKey& k) { add(kReceived, k); }
    /// Gives sent frame `id` a reason, should it turn out lost. False: it is no longer waiting
    /// (matched, or final).
    bool explain(std::uint64_t id, DropReason why);
    /// Makes every waiting frame final.
    void finish();
    const Counts& counts() const { return counts_; }
    /// Frames waiting on either side (for tests of the bound).
    std::size_t waiting() const;

private:
    enum Side : unsigned { kSent = 0, kReceived = 1 };
    struct Item {
        FrameKey key;
        std::uint64_t id;
        DropReason why;
    };
    std::array<std::deque<Item>, 2> pending_, overtaken_;
    std::deque<FrameKey> recent_; // the last kWindow matched frames, to tell a duplicate
    std::uint64_t next_id_ = 0;
    Counts counts_;

    std::uint64_t add(Side s, const FrameKey& k);
    void overtake(Side s, std::size_t n);
    void finalize(Side s, const Item& it);
    void matched(const FrameKey& k);
};

/// The passive decoder of one port and its two comparisons.
class LineObserver {
public:
    enum Dir : unsigned { host_to_controller = 0, controller_to_host = 1 };

    struct DirCounts {
        std::uint64_t enqs = 0;
        std::uint64_t frames_offered = 0; // SOH..ETX complete on the line
        std::uint64_t frames_bad = 0;     // of those, not a valid frame as received (checksum, line error, ...)
        std::uint64_t frames_eot = 0;     // valid frames the other side answered with EOT
        std::uint64_t naks = 0;           // NAKs the other side answered this side's ENQ or frame with
        std::uint64_t retries = 0;        // frames offered again after an attempt without EOT
        std::uint64_t abandoned = 0;      // valid frames never acknowledged: a different one followed, or the run ended
    };

    // ---- the line (from SerialLine::on_deliver) ----
    /// A character as its receiver decoded it; `error`: parity or framing error.
    void line_char(Dir d, std::uint8_t byte, bool error);
    /// The receiver saw a BREAK begin: a frame in progress from that side is cut.
    void line_break(Dir d);

    // ---- the main CPU's DP-RAM side ----
    void main_received(const FrameKey& k) { commands_.received(k); }
    /// A response the main CPU handed to DP-RAM (every chunk acknowledged by the comm CPU).
    void main_handed(const FrameKey& k);
    /// The comm CPU gave up on the response it was sending (mailbox word 0x4p or 0x5p).
    void response_given_up();
    /// The comm CPU reset the port: its transmit ring, and every response in it, is dropped.
    void port_reset();

    /// End of the run: frames still unanswered are abandoned, unmatched ones final.
    void finish();

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

private:
    enum class Await : std::uint8_t { none, enq, frame };
    struct Sender {
        proto::FrameDecoder decoder;
        bool collecting = false;
        Await await = Await::none;
        bool open = false;             // the last frame offered got no EOT yet
        bool last_good = false;        // ... and it was valid as received
        std::optional<FrameKey> last;  // the last valid frame offered without EOT
        DirCounts counts;
    };
    std::array<Sender, 2> dir_;
    std::uint64_t enq_collisions_ = 0, breaks_ = 0;
    SequenceMatcher commands_, responses_;
    // Responses in the comm CPU's transmit ring, oldest first (it sends and gives up in order).
    std::deque<std::uint64_t> in_ring_;

    void control(Dir d, std::uint8_t byte);
    void frame_done(Dir d, bool good);
    void acknowledged(Dir d);
};

} // namespace rcsim
