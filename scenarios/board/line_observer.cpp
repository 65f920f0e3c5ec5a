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

// ---------------------------------------------------------------------------------------------
// SequenceMatcher

std::uint64_t SequenceMatcher::add(Side s, const FrameKey& k) {
    const Side o = s == kSent ? kReceived : kSent;
    ++(s == kSent ? counts_.sent : counts_.received);
    auto& other = pending_[o];
    const auto it = std::find_if(other.begin(), other.end(), [&k](const Item& i) { return i.key == k; });
    if (it != other.end()) {
        // Equal frames are interchangeable: a drop reason belongs to one that stays unmatched.
        if (it->why != DropReason::none) {
            const auto spare = std::find_if(it + 1, other.end(), [&k](const Item& i) {
                return i.key == k && i.why == DropReason::none;
            });
            if (spare != other.end()) std::swap(it->why, spare->why);
        }
        // Everything older than the pair, on both sides, was overtaken by it.
        const std::size_t before = static_cast<std::size_t>(it - other.begin());
        overtake(o, before);
        other.pop_front(); // the match
        overtake(s, pending_[s].size());
        matched(k);
        return next_id_++;
    }
    pending_[s].push_back(Item{k, next_id_, DropReason::none});
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
    // An equal frame still unmatched on the other side: the two crossed, one reordering.
    for (auto* q : {&overtaken_[o], &pending_[o]}) {
        const auto it = std::find_if(q->begin(), q->end(), [&item](const Item& i) { return i.key == item.key; });
        if (it != q->end()) {
            q->erase(it);
            matched(item.key);
            ++counts_.reordered;
            return;
        }
    }
    if (s == kReceived) {
        const bool again = std::find(recent_.begin(), recent_.end(), item.key) != recent_.end();
        ++(again ? counts_.duplicates : counts_.unexpected);
    } else if (item.why == DropReason::gave_up) {
        ++counts_.dropped_gave_up;
    } else if (item.why == DropReason::port_reset) {
        ++counts_.dropped_port_reset;
    } else {
        ++counts_.lost;
    }
}

void SequenceMatcher::matched(const FrameKey& k) {
    ++counts_.matched;
    recent_.push_back(k);
    if (recent_.size() > kWindow) recent_.pop_front();
}

bool SequenceMatcher::explain(std::uint64_t id, DropReason why) {
    for (auto* q : {&pending_[kSent], &overtaken_[kSent]})
        for (Item& i : *q)
            if (i.id == id) {
                i.why = why;
                return true;
            }
    return false;
}

void SequenceMatcher::finish() {
    // Oldest first on each side; the sent side first, so a crossing pair is found from either.
    for (Side s : {kSent, kReceived}) {
        overtake(s, pending_[s].size());
        while (!overtaken_[s].empty()) {
            const Item it = overtaken_[s].front();
            overtaken_[s].pop_front();
            finalize(s, it);
        }
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
    if (good) key = frame_key(s.decoder.frame());
    else ++s.counts.frames_bad;
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
    if (key && d == controller_to_host) responses_.received(*key);
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
        // The commands' intention: what the host was told was delivered.
        if (d == host_to_controller) commands_.sent(*s.last);
    }
    // The comm CPU has its EOT: the oldest response in its ring is done (valid or not).
    if (d == controller_to_host && !in_ring_.empty()) in_ring_.pop_front();
    s.open = false;
    s.last.reset();
    s.await = Await::none;
}

void LineObserver::line_break(Dir d) {
    ++breaks_;
    dir_[d].collecting = false;
}

void LineObserver::main_handed(const FrameKey& k) {
    in_ring_.push_back(responses_.sent(k));
    // The firmware's ring holds at most 8 frames; an id this old can no longer be explained.
    if (in_ring_.size() > SequenceMatcher::kWindow) in_ring_.pop_front();
}

void LineObserver::response_given_up() {
    if (in_ring_.empty()) return;
    responses_.explain(in_ring_.front(), DropReason::gave_up);
    in_ring_.pop_front();
}

void LineObserver::port_reset() {
    for (std::uint64_t id : in_ring_) responses_.explain(id, DropReason::port_reset);
    in_ring_.clear();
}

void LineObserver::finish() {
    for (Sender& s : dir_) {
        if (s.open && s.last) ++s.counts.abandoned;
        s.open = false;
        s.last.reset();
    }
    commands_.finish();
    responses_.finish();
}

} // namespace rcsim
