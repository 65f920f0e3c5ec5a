#include "scenarios/board/line_observer.h"

#include <algorithm>

namespace rcsim {

FrameKey frame_key(const std::string& token, std::uint8_t bch, const std::string& data) {
    // FNV-1a, 64 bit. BCH goes between token and data as one byte; the token is always two
    // characters, so the fields cannot slide into each other.
    std::uint64_t h = 0xcbf29ce484222325ULL;
    auto mix = [&h](unsigned char c) {
        h ^= c;
        h *= 0x100000001b3ULL;
    };
    for (unsigned char c : token) mix(c);
    mix(bch);
    for (unsigned char c : data) mix(c);
    return {h, static_cast<std::uint32_t>(data.size())};
}

std::string frame_label(const std::string& token, std::uint8_t bch, const std::string& data) {
    static const char* hex = "0123456789ABCDEF";
    std::string s = token + ' ' + hex[bch >> 4] + hex[bch & 15] + " \"";
    constexpr std::size_t kShown = 16;
    for (std::size_t i = 0; i < data.size() && i < kShown; ++i) {
        const unsigned char c = static_cast<unsigned char>(data[i]);
        s += c >= 0x20 && c < 0x7F ? static_cast<char>(c) : '?';
    }
    if (data.size() > kShown) s += "...";
    return s + "\" (" + std::to_string(data.size()) + " bytes)";
}

const char* kind_name(FrameEvent::Kind k) {
    switch (k) {
    case FrameEvent::Kind::lost: return "lost";
    case FrameEvent::Kind::gave_up: return "gave_up";
    case FrameEvent::Kind::port_reset: return "port_reset";
    case FrameEvent::Kind::duplicate: return "duplicate";
    case FrameEvent::Kind::unexpected: return "unexpected";
    case FrameEvent::Kind::reordered: return "reordered";
    }
    return "?";
}

// ---------------------------------------------------------------------------------------------
// SequenceMatcher

std::uint64_t SequenceMatcher::add(Side s, const FrameKey& k, Note note) {
    const Side o = s == kSent ? kReceived : kSent;
    ++(s == kSent ? counts_.sent : counts_.received);
    auto& other = pending_[o];
    const auto it = std::find_if(other.begin(), other.end(), [&k](const Item& i) { return i.key == k; });
    if (it != other.end()) {
        // Equal frames are interchangeable: a drop reason belongs to one that stays unmatched.
        if (it->drop.why != DropReason::none) {
            const auto spare = std::find_if(it + 1, other.end(), [&k](const Item& i) {
                return i.key == k && i.drop.why == DropReason::none;
            });
            if (spare != other.end()) std::swap(it->drop, spare->drop);
        }
        // Everything older than the pair, on both sides, was overtaken by it.
        const std::size_t before = static_cast<std::size_t>(it - other.begin());
        overtake(o, before);
        other.pop_front(); // the match
        overtake(s, pending_[s].size());
        matched(k);
        mark_copies(k);
        return next_id_++;
    }
    Item item{k, next_id_, std::move(note), {}};
    item.drop.cause = std::move(item.note.cause); // a sent frame's cause goes with its drop
    item.copy = s == kReceived && std::find(recent_.begin(), recent_.end(), k) != recent_.end();
    pending_[s].push_back(std::move(item));
    if (pending_[s].size() > kWindow) overtake(s, 1);
    return next_id_++;
}

void SequenceMatcher::overtake(Side s, std::size_t n) {
    for (; n > 0; --n) {
        overtaken_[s].push_back(pending_[s].front());
        pending_[s].pop_front();
        if (overtaken_[s].size() > kWindow) {
            const Item it = overtaken_[s].front();
            overtaken_[s].pop_front();
            finalize(s, it);
        }
    }
}

void SequenceMatcher::finalize(Side s, const Item& item) {
    const Side o = s == kSent ? kReceived : kSent;
    using K = FrameEvent::Kind;
    // An equal frame still unmatched on the other side: the two crossed, one reordering.
    for (auto* q : {&overtaken_[o], &pending_[o]}) {
        const auto it = std::find_if(q->begin(), q->end(), [&item](const Item& i) { return i.key == item.key; });
        if (it != q->end()) {
            q->erase(it);
            matched(item.key);
            ++counts_.reordered;
            list(unexplained_, {K::reordered, item.note.label, item.note.time_us, {}});
            return;
        }
    }
    if (s == kReceived) {
        const bool again = item.copy || std::find(recent_.begin(), recent_.end(), item.key) != recent_.end();
        ++(again ? counts_.duplicates : counts_.unexpected);
        list(unexplained_, {again ? K::duplicate : K::unexpected, item.note.label, item.note.time_us, {}});
        return;
    }
    FrameEvent e{K::lost, item.note.label, item.note.time_us, item.drop.cause};
    if (item.drop.why == DropReason::gave_up) {
        ++counts_.dropped_gave_up;
        e.kind = K::gave_up;
    } else if (item.drop.why == DropReason::port_reset) {
        ++counts_.dropped_port_reset;
        e.kind = K::port_reset;
    } else {
        ++counts_.lost;
    }
    if (item.drop.why != DropReason::none) e.time_us = item.drop.time_us;
    if (e.cause.empty()) {
        list(unexplained_, std::move(e));
    } else {
        ++counts_.expected;
        list(expected_, std::move(e));
    }
}

void SequenceMatcher::list(std::vector<FrameEvent>& v, FrameEvent e) {
    if (v.size() < kListed) v.push_back(std::move(e));
}

// The received frames equal to one just matched are copies of it, should they stay unmatched: they
// are told from an unexpected frame now, while the original is among the recent ones, not when
// they become final, maybe kWindow matches later.
void SequenceMatcher::mark_copies(const FrameKey& k) {
    for (auto* q : {&pending_[kReceived], &overtaken_[kReceived]})
        for (Item& i : *q)
            if (i.key == k) i.copy = true;
}

void SequenceMatcher::matched(const FrameKey& k) {
    ++counts_.matched;
    recent_.push_back(k);
    if (recent_.size() > kWindow) recent_.pop_front();
}

SequenceMatcher::Item* SequenceMatcher::waiting_sent(std::uint64_t id) {
    for (auto* q : {&pending_[kSent], &overtaken_[kSent]})
        for (Item& i : *q)
            if (i.id == id) return &i;
    return nullptr;
}

bool SequenceMatcher::explain(std::uint64_t id, DropReason why, double time_us) {
    Item* i = waiting_sent(id);
    if (!i) return false;
    i->drop.why = why;
    i->drop.time_us = time_us;
    return true;
}

bool SequenceMatcher::blame(std::uint64_t id, const ScenarioCause& cause, bool replace) {
    Item* i = waiting_sent(id);
    if (!i) return false;
    if (replace || i->drop.cause.empty()) i->drop.cause = cause;
    return true;
}

void SequenceMatcher::finish(bool interrupted) {
    if (!interrupted) {
        // Oldest first on each side; the sent side first, so a crossing pair is found from either.
        for (Side s : {kSent, kReceived}) {
            overtake(s, pending_[s].size());
            while (!overtaken_[s].empty()) {
                const Item it = overtaken_[s].front();
                overtaken_[s].pop_front();
                finalize(s, it);
            }
        }
        return;
    }
    // Stopped by a signal: what a later frame overtook is final as ever; what still waits in
    // order may yet have arrived (the record lags or leads by the frames in flight), unless it
    // was dropped with a reason already.
    for (Side s : {kSent, kReceived})
        while (!overtaken_[s].empty()) {
            const Item it = overtaken_[s].front();
            overtaken_[s].pop_front();
            finalize(s, it);
        }
    for (Side s : {kSent, kReceived})
        while (!pending_[s].empty()) {
            const Item it = pending_[s].front();
            pending_[s].pop_front();
            if (s == kSent && it.drop.why != DropReason::none) finalize(s, it);
            else ++counts_.in_flight;
        }
}

std::size_t SequenceMatcher::waiting() const {
    return pending_[0].size() + pending_[1].size() + overtaken_[0].size() + overtaken_[1].size();
}

// ---------------------------------------------------------------------------------------------
// LineObserver

void LineObserver::line_char(Dir d, std::uint8_t byte, bool error) {
    Sender& s = dir_[d];
    if (s.collecting) {
        if (byte == proto::SOH && !error) { // a new frame: the partial one is given up
            s.decoder.reset();
            s.decoder.feed(byte);
            return;
        }
        const auto r = s.decoder.feed(byte, error);
        if (r == proto::FrameDecoder::Result::more) return;
        s.collecting = false;
        frame_done(d, r == proto::FrameDecoder::Result::good);
        return;
    }
    if (error) return; // a damaged character is no control byte for its receiver either
    if (byte == proto::SOH) {
        s.collecting = true;
        s.decoder.reset();
        s.decoder.feed(byte);
        return;
    }
    control(d, byte);
}

// ENQ, ACK, NAK, EOT from side d answer (or start) a transfer; other bytes outside a frame are
// line noise to a receiver in the protocol and are ignored.
void LineObserver::control(Dir d, std::uint8_t byte) {
    Sender& me = dir_[d];
    Sender& peer = dir_[d == host_to_controller ? controller_to_host : host_to_controller];
    const Dir pd = d == host_to_controller ? controller_to_host : host_to_controller;
    switch (byte) {
    case proto::ENQ:
        ++me.counts.enqs;
        if (!me.open) me.cause = {}; // a fresh transfer: the causes before it are not its own
        if (peer.await == Await::enq) ++enq_collisions_;
        me.await = Await::enq;
        break;
    case proto::ACK:
        if (peer.await == Await::enq) peer.await = Await::none;
        break;
    case proto::NAK:
        if (peer.await != Await::none) ++peer.counts.naks;
        peer.await = Await::none;
        break;
    case proto::EOT:
        if (peer.await == Await::frame) acknowledged(pd);
        break;
    default: break;
    }
}

void LineObserver::frame_done(Dir d, bool good) {
    Sender& s = dir_[d];
    ++s.counts.frames_offered;
    std::optional<FrameKey> key;
    if (good) {
        const proto::Frame& f = s.decoder.frame();
        key = frame_key(f);
        s.last_label = frame_label(f.token, f.bch, f.data);
    } else {
        ++s.counts.frames_bad;
    }
    if (s.open) {
        // Offered again after an attempt without EOT: a retry, unless it is a different valid
        // frame, which means the sender gave the last one up.
        if (key && s.last && *key != *s.last) ++s.counts.abandoned;
        else ++s.counts.retries;
    }
    if (key) s.last = key;
    s.open = true;
    s.last_good = good;
    s.await = Await::frame;
    // The responses' record: what reached the host intact, EOT or not.
    if (key && d == controller_to_host) responses_.received(*key, {s.last_label, now(), {}});
    if (on_frame) on_frame(d, good, s.decoder.frame());
}

LineObserver::SenderState LineObserver::state(Dir d) const {
    const Sender& s = dir_[d];
    if (s.collecting) return SenderState::frame_on_line;
    switch (s.await) {
    case Await::enq: return SenderState::enq_sent;
    case Await::frame: return SenderState::awaiting_eot;
    default: return SenderState::idle;
    }
}

// The other side answered side d's frame with EOT.
void LineObserver::acknowledged(Dir d) {
    Sender& s = dir_[d];
    if (s.last_good) {
        ++s.counts.frames_eot;
        // The commands' intention: what the host was told was delivered, with the first cause
        // that hit the port during its transfer.
        if (d == host_to_controller) commands_.sent(*s.last, {s.last_label, now(), s.cause});
    }
    // The comm CPU has its EOT: the oldest response in its ring is done (valid or not).
    if (d == controller_to_host && !in_ring_.empty()) in_ring_.pop_front();
    s.end_transfer();
}

void LineObserver::line_break(Dir d) {
    ++breaks_;
    dir_[d].collecting = false;
    if (d != host_to_controller) return; // the controller's own BREAK is a cause only if injected (line_fault)
    break_before_reset_ = {"BREAK from the host", now()};
    line_fault(break_before_reset_);
}

void LineObserver::line_fault(const ScenarioCause& c) {
    // The command being transferred (from its ENQ on), and the response being sent: the oldest
    // in the comm CPU's ring.
    Sender& h = dir_[host_to_controller];
    if (h.cause.empty()) h.cause = c;
    if (!in_ring_.empty()) responses_.blame(in_ring_.front(), c);
}

void LineObserver::main_handed(const FrameKey& k, std::string label) {
    in_ring_.push_back(responses_.sent(k, {std::move(label), now(), {}}));
    // The firmware's ring holds at most 8 frames; an id this old can no longer be explained.
    if (in_ring_.size() > SequenceMatcher::kWindow) in_ring_.pop_front();
}

void LineObserver::response_given_up() {
    if (in_ring_.empty()) return;
    responses_.explain(in_ring_.front(), DropReason::gave_up, now());
    in_ring_.pop_front();
}

void LineObserver::port_reset(bool by_main_cpu) {
    const double t = now();
    // The reset's own cause replaces whatever hit the ring before: it is what dropped them.
    ScenarioCause cause;
    if (!by_main_cpu && !break_before_reset_.empty() && t - break_before_reset_.time_us <= kBreakResetUs) {
        cause = break_before_reset_;
        cause.what = "port reset after a " + cause.what;
    }
    if (!by_main_cpu) break_before_reset_ = {};
    // The controller's transfer ends here: a frame cut before its ETX never ends on the line, and
    // the controller's next ACK and EOT answer the host again (they are not that frame's bytes).
    dir_[controller_to_host].collecting = false;
    dir_[controller_to_host].end_transfer();
    for (std::uint64_t id : in_ring_) {
        responses_.blame(id, cause, true);
        responses_.explain(id, DropReason::port_reset, t);
    }
    in_ring_.clear();
}

void LineObserver::finish(bool interrupted) {
    for (Sender& s : dir_) {
        if (s.open && s.last && !interrupted) ++s.counts.abandoned; // interrupted: it was in flight
        s.open = false;
        s.last.reset();
    }
    commands_.finish(interrupted);
    responses_.finish(interrupted);
}

} // namespace rcsim
