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

void SequenceMatcher::sent(FrameId id, Note note) {
    ++counts_.sent;
    const auto e = std::find_if(early_.begin(), early_.end(), [id](const Item& i) { return i.id == id; });
    if (e == early_.end()) {
        Item item{id, std::move(note), {}};
        // A sent frame's cause goes with its drop, unless it has one for its loss.
        item.drop.cause = item.note.loss_cause ? *item.note.loss_cause : item.note.cause;
        waiting_.push_back(std::move(item));
        if (waiting_.size() > kWindow) {
            lost(waiting_.front());
            waiting_.pop_front();
        }
        return;
    }
    // The record led: every frame sent before this one and still waiting was overtaken by it; and
    // if a frame made after it (ids grow in the order frames are made) was received before it,
    // this one came late.
    for (Item& w : waiting_) w.overtaken = true;
    if (std::any_of(early_.begin(), e, [id](const Item& i) { return i.id > id; })) {
        ++counts_.reordered;
        list(unexplained_, {FrameEvent::Kind::reordered, e->note.label, e->note.time_us, {}, {}, false});
    }
    early_.erase(e);
    matched(id, note.cause);
    // Its other copies that arrived ahead of it are duplicates, now that it is matched.
    for (auto it = early_.begin(); it != early_.end();) {
        if (it->id != id) {
            ++it;
            continue;
        }
        copy(it->note, note.cause);
        it = early_.erase(it);
    }
}

void SequenceMatcher::received(FrameId id, Note note) {
    ++counts_.received;
    const auto w = std::find_if(waiting_.begin(), waiting_.end(), [id](const Item& i) { return i.id == id; });
    if (w != waiting_.end()) {
        for (auto older = waiting_.begin(); older != w; ++older) older->overtaken = true;
        if (w->overtaken) {
            ++counts_.reordered;
            list(unexplained_, {FrameEvent::Kind::reordered, note.label, note.time_us, {}, {}, false});
        }
        matched(id, w->drop.cause);
        waiting_.erase(w);
        return;
    }
    if (const Matched* m = recent(id)) {
        copy(note, m->cause);
        return;
    }
    Item item{id, std::move(note), {}};
    if (id == kNoFrameId) {
        never_sent(item);
        return;
    }
    early_.push_back(std::move(item));
    if (early_.size() > kWindow) {
        never_sent(early_.front());
        early_.pop_front();
    }
}

void SequenceMatcher::matched(FrameId id, ScenarioCause cause) {
    ++counts_.matched;
    remember(id, std::move(cause));
}

void SequenceMatcher::remember(FrameId id, ScenarioCause cause) {
    recent_.push_back({id, std::move(cause)});
    if (recent_.size() > kWindow) recent_.pop_front();
}

SequenceMatcher::Matched* SequenceMatcher::recent(FrameId id) {
    if (id == kNoFrameId) return nullptr;
    for (Matched& m : recent_)
        if (m.id == id) return &m;
    return nullptr;
}

// A received frame whose id was matched (or found unexpected) before: a duplicate, listed with
// what hit its transfer, if anything did.
void SequenceMatcher::copy(const Note& note, const ScenarioCause& cause) {
    ++counts_.duplicates;
    const ScenarioCause& c = note.cause.empty() ? cause : note.cause;
    if (!c.empty()) ++counts_.after_fault;
    list(unexplained_, {FrameEvent::Kind::duplicate, note.label, note.time_us, c, {}, false});
}

// A received frame that was never sent: unexpected, and its later copies duplicates of it.
void SequenceMatcher::never_sent(const Item& it) {
    if (const Matched* m = recent(it.id)) {
        copy(it.note, m->cause);
        return;
    }
    ++counts_.unexpected;
    if (!it.note.cause.empty()) ++counts_.after_fault;
    list(unexplained_, {FrameEvent::Kind::unexpected, it.note.label, it.note.time_us, it.note.cause, {}, false});
    if (it.id == kNoFrameId) return;
    remember(it.id, it.note.cause);
}

void SequenceMatcher::lost(const Item& item) {
    using K = FrameEvent::Kind;
    FrameEvent e{K::lost, item.note.label, item.note.time_us, item.drop.cause, item.drop.attempts, false};
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
    // A give-up is the scenario's only when a cause hit every attempt the protocol owed.
    e.expected = !e.cause.empty() && (!e.attempts || e.attempts->all_owed_hit());
    if (!e.expected) {
        list(unexplained_, std::move(e));
    } else {
        ++counts_.expected;
        list(expected_, std::move(e));
    }
}

void SequenceMatcher::list(std::vector<FrameEvent>& v, FrameEvent e) {
    if (v.size() < kListed) v.push_back(std::move(e));
}

bool SequenceMatcher::explain(FrameId id, DropReason why, double time_us, std::optional<Attempts> attempts) {
    for (Item& i : waiting_)
        if (i.id == id) {
            i.drop.why = why;
            i.drop.time_us = time_us;
            i.drop.attempts = attempts;
            return true;
        }
    return false;
}

bool SequenceMatcher::blame(FrameId id, const ScenarioCause& cause, bool replace) {
    for (Item& i : waiting_)
        if (i.id == id) {
            if (replace || i.drop.cause.empty()) i.drop.cause = cause;
            return true;
        }
    if (Matched* m = recent(id))
        if (replace || m->cause.empty()) m->cause = cause;
    return false;
}

void SequenceMatcher::finish(bool interrupted) {
    // Stopped by a signal, what still waits in order may yet have arrived (the record lags or
    // leads by the frames in flight), unless it was dropped with a reason already; what a later
    // frame overtook is final as ever.
    for (const Item& it : waiting_) {
        if (interrupted && !it.overtaken && it.drop.why == DropReason::none) ++counts_.in_flight;
        else lost(it);
    }
    waiting_.clear();
    for (const Item& it : early_) {
        if (interrupted && !recent(it.id)) ++counts_.in_flight;
        else never_sent(it);
    }
    early_.clear();
}

// ---------------------------------------------------------------------------------------------
// LineObserver

void LineObserver::line_char(Dir d, std::uint8_t byte, bool error) {
    Sender& s = dir_[d];
    if (s.collecting) {
        extend_attempt(d); // a long frame outlasts T1: the attempt lasts while it is on the line
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
        begin_attempt(d, now());
        me.attempt_cause = {};       // nor those before this attempt its own
        if (peer.await == Await::enq) ++enq_collisions_;
        me.await = Await::enq;
        break;
    case proto::ACK:
        if (peer.await == Await::enq) {
            peer.await = Await::none;
            extend_attempt(pd); // its frame follows
        }
        break;
    case proto::NAK:
        if (peer.await != Await::none) {
            ++peer.counts.naks;
            peer.attempt_until = now(); // that attempt is over: what comes before the retry is not its
        }
        // The controller refused a valid command: it will not forward it.
        if (d == controller_to_host && peer.await == Await::frame && peer.last_good && !offered_.empty() &&
            offered_.back().id == peer.transfer)
            offered_.pop_back();
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
        if (key && s.last && *key != *s.last) {
            ++s.counts.abandoned;
            // The sender gave the last frame up: this attempt is the new frame's first.
            if (s.attempts.made > 0) s.attempts = {1, s.attempt_hit ? 1u : 0u};
        } else {
            ++s.counts.retries;
        }
    }
    if (key) {
        if (!s.open || !s.last || *key != *s.last) s.transfer = next_id_++; // a retry keeps its id
        s.last = key;
        if (d == host_to_controller) keep_last(offered_, {s.transfer, *key, s.cause});
    }
    s.open = true;
    s.last_good = good;
    s.await = Await::frame;
    extend_attempt(d); // T1 from its ETX
    // The responses' record: what reached the host intact, EOT or not.
    if (key && d == controller_to_host) responses_.received(response_id(*key), {s.last_label, now(), {}, {}});
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
        // Its loss is explained by the attempt that got the EOT only (class comment).
        if (d == host_to_controller) commands_.sent(s.transfer, {s.last_label, now(), s.cause, s.attempt_cause});
    }
    // The comm CPU has its EOT: the oldest response in its ring is done (valid or not).
    if (d == controller_to_host && !in_ring_.empty()) {
        keep_last(sent_, in_ring_.front());
        in_ring_.pop_front();
    }
    s.end_transfer();
}

void LineObserver::line_break(Dir d) {
    ++breaks_;
    dir_[d].collecting = false;
    if (d != host_to_controller) return; // the controller's own BREAK is a cause only if injected (line_fault)
    break_before_reset_ = {"BREAK from the host", now()};
    line_fault(break_before_reset_);
}

void LineObserver::begin_attempt(Dir d, double t) {
    Sender& s = dir_[d];
    ++s.attempts.made;
    s.attempt_hit = false;
    s.attempt_until = t + kT1Us + kAttemptSlackUs;
}

// Every attempt live at t, either sender's, was hit (once each).
void LineObserver::hit_attempts(double t) {
    for (Sender& s : dir_) {
        if (!s.attempt_live(t) || s.attempt_hit) continue;
        s.attempt_hit = true;
        ++s.attempts.hit;
    }
}

// Whether the character a cause destroyed was its sender's ENQ, the start of an attempt the
// receiver never saw. The byte, when the line kept it; otherwise (its bits altered) an ENQ is the
// only character a side sends with no attempt of either side live, and the controller sends one
// only with a response in its ring.
bool LineObserver::destroyed_enq(const HitChar& h, double t) const {
    if (h.byte) return *h.byte == proto::ENQ;
    const Dir peer = h.from == host_to_controller ? controller_to_host : host_to_controller;
    if (dir_[h.from].attempt_live(t) || dir_[peer].attempt_live(t)) return false;
    return h.from == host_to_controller || !in_ring_.empty();
}

void LineObserver::line_fault(const ScenarioCause& c, std::optional<HitChar> hit) {
    const double t = now();
    if (hit && destroyed_enq(*hit, t)) {
        begin_attempt(hit->from, t);
        dir_[hit->from].attempt_cause = {};
    }
    hit_attempts(t);
    // The command being transferred (from its ENQ on), and the response being sent: the oldest
    // in the comm CPU's ring.
    Sender& h = dir_[host_to_controller];
    if (h.attempt_cause.empty() && h.attempt_live(t)) h.attempt_cause = c;
    if (h.cause.empty()) {
        h.cause = c;
        // The command of this transfer already on the line shares the cause.
        if (h.open)
            for (Carried& o : offered_)
                if (o.id == h.transfer && o.cause.empty()) o.cause = c;
    }
    if (!in_ring_.empty()) responses_.blame(in_ring_.front().id, c);
}

void LineObserver::keep_last(std::deque<Carried>& q, Carried c) {
    q.push_back(std::move(c));
    if (q.size() > SequenceMatcher::kWindow) q.pop_front();
}

// The id of a command the main CPU reassembled: the oldest equal one offered (the comm CPU
// forwards in order; those before it it refused or the host gave up, and they leave with it),
// or, when none waits, the last equal one already found (a copy forwarded again).
FrameId LineObserver::command_id(const FrameKey& k, ScenarioCause& cause) {
    const auto it = std::find_if(offered_.begin(), offered_.end(), [&k](const Carried& c) { return c.key == k; });
    if (it != offered_.end()) {
        const Carried found = *it;
        offered_.erase(offered_.begin(), it + 1);
        keep_last(forwarded_, found);
        cause = found.cause;
        return found.id;
    }
    const auto again =
        std::find_if(forwarded_.rbegin(), forwarded_.rend(), [&k](const Carried& c) { return c.key == k; });
    if (again == forwarded_.rend()) return kNoFrameId;
    cause = again->cause;
    return again->id;
}

// The id of a response that reached the host intact: the oldest equal one in the ring (the one
// being sent, or being sent again), or, when none is there, the last equal one it had EOT for.
FrameId LineObserver::response_id(const FrameKey& k) const {
    for (const Carried& c : in_ring_)
        if (c.key == k) return c.id;
    for (auto it = sent_.rbegin(); it != sent_.rend(); ++it)
        if (it->key == k) return it->id;
    return kNoFrameId;
}

void LineObserver::main_received(const FrameKey& k, std::string label) {
    ScenarioCause cause;
    const FrameId id = command_id(k, cause);
    commands_.received(id, {std::move(label), now(), std::move(cause), {}});
}

void LineObserver::main_handed(const FrameKey& k, std::string label) {
    const FrameId id = next_id_++;
    responses_.sent(id, {std::move(label), now(), {}, {}});
    // The firmware's ring holds at most 8 frames; an id this old can no longer be explained.
    keep_last(in_ring_, {id, k, {}});
}

void LineObserver::response_given_up() {
    if (in_ring_.empty()) return;
    // The give-up ends the comm CPU's attempts at that frame (its next ENQ begins the next one's);
    // `open` stays, so the next frame offered still counts it abandoned (DirCounts).
    Sender& c = dir_[controller_to_host];
    responses_.explain(in_ring_.front().id, DropReason::gave_up, now(), c.attempts);
    c.end_attempts();
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
    for (const Carried& c : in_ring_) {
        responses_.blame(c.id, cause, true);
        responses_.explain(c.id, DropReason::port_reset, t);
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
