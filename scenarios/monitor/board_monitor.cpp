// rcsim — the remote monitor's simulation side (see board_monitor.h, docs/monitor.md).
#include "scenarios/monitor/board_monitor.h"

#include "models/clock.h"
#include "models/plumbing/config_error.h"
#include "models/plumbing/hex.h"
#include "models/plumbing/stop_signal.h"
#include "scenarios/monitor/monitor_page.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <thread>

namespace rcsim::monitor {

namespace {

using sc_core::sc_time;
constexpr unsigned kIrqLevels = 4; // IR0..IR2 the 82510s, IR3 the DP-RAM's INT_L
// Slices of simulated time between two services: adapted so one takes about 2..8 ms of wall
// time (a client's request waits at most about that long), within these bounds.
const sc_time kMinSlice = sc_core::sc_time(10, sc_core::SC_US);
const sc_time kMaxSlice = sc_core::sc_time(100, sc_core::SC_MS);
constexpr auto kPublishEvery = std::chrono::milliseconds(50); // GET /api/v1/snapshot freshness
constexpr double kMaxStepMs = 60'000;
// An hour is the longest run (docs/scenarios.md "Limits"): a monitored run, and any step in it,
// stops there whatever its duration_s (0: until a host ends the session).
const sc_time kLongestRun = sc_core::sc_time(3600, sc_core::SC_SEC);
constexpr std::size_t kMaxPathPoints = 4000; // per update; the rest follows in the next ones
constexpr std::size_t kMaxQueuedFrames = 64; // send_frame: commands waiting at a protocol host
constexpr std::size_t kMaxPendingFaults = 64; // inject_fault: faults waiting for a side's next characters

} // namespace

/// A request's arguments, read without exceptions. The first argument that is missing, of the
/// wrong type or out of range becomes the refusal the client is answered with (the client stays);
/// later reads return their fallback. Exceptions stay out of this path on purpose: the requests
/// are served on the main thread between two sc_start()s, and in a sanitizer build ASan takes that
/// thread for one without a stack once SystemC has switched back to it (its coroutine switches
/// announce the main coroutine with an empty stack), so a throw there cannot unpoison the frames it
/// unwinds and leaves their stack poison behind for the next call to trip over.
class Args {
public:
    explicit Args(const nlohmann::json& m) : m_(m) {}
    /// A value as a refusal names it: its JSON, cut short (a client may send 64 KiB of it).
    static std::string shown(const nlohmann::json& v) {
        std::string t = v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
        if (t.size() > 40) t = t.substr(0, 40) + "...";
        return t;
    }
    const nlohmann::json& json() const { return m_; }
    bool ok() const { return refusal_.empty(); }
    const std::string& refusal() const { return refusal_; }
    /// Adds to the refusal, if there is one.
    void amend(const std::string& more) {
        if (!refusal_.empty()) refusal_ += more;
    }
    /// Refuses the request with `why` (the first refusal counts); returns an empty reply.
    nlohmann::json refuse(const std::string& why) {
        if (refusal_.empty()) refusal_ = why;
        return nlohmann::json::object();
    }

    double number(const char* key, double lo, double hi, std::optional<double> fallback = {}) {
        const double none = fallback.value_or(lo);
        if (!m_.contains(key)) {
            if (!fallback) refuse(std::string("missing \"") + key + "\"");
            return none;
        }
        if (!m_[key].is_number()) {
            refuse(std::string("\"") + key + "\" = " + shown(m_[key]) + " must be a number");
            return none;
        }
        const double v = m_[key].get<double>();
        if (!(v >= lo && v <= hi)) {
            refuse(std::string("\"") + key + "\" = " + shown(m_[key]) + " is out of range [" +
                   nlohmann::json(lo).dump() + ", " + nlohmann::json(hi).dump() + "]");
            return none;
        }
        return v;
    }

    /// A whole number in [lo, hi]: 2.7 is refused, not taken as 2 (2.0 is 2).
    std::int64_t integer(const char* key, std::int64_t lo, std::int64_t hi, std::optional<std::int64_t> fallback = {}) {
        if (m_.contains(key) && m_[key].is_number() &&
            !(m_[key].get<double>() >= static_cast<double>(lo) && m_[key].get<double>() <= static_cast<double>(hi))) {
            refuse(std::string("\"") + key + "\" = " + shown(m_[key]) + " is out of range " + std::to_string(lo) + ".." +
                   std::to_string(hi));
            return fallback.value_or(lo);
        }
        const auto l = static_cast<double>(lo), h = static_cast<double>(hi);
        const double v = fallback ? number(key, l, h, static_cast<double>(*fallback)) : number(key, l, h);
        if (!ok()) return fallback.value_or(lo);
        if (v != std::floor(v)) {
            refuse(std::string("\"") + key + "\" = " + shown(m_[key]) + " must be a whole number " +
                   std::to_string(lo) + ".." + std::to_string(hi));
            return fallback.value_or(lo);
        }
        return static_cast<std::int64_t>(v);
    }

    bool boolean(const char* key, bool fallback) {
        if (!m_.contains(key)) return fallback;
        if (!m_[key].is_boolean()) {
            refuse(std::string("\"") + key + "\" = " + shown(m_[key]) + " must be true or false");
            return fallback;
        }
        return m_[key].get<bool>();
    }

    std::string string(const char* key, std::optional<std::string> fallback = {}) {
        if (!m_.contains(key)) {
            if (!fallback) refuse(std::string("missing \"") + key + "\"");
            return fallback.value_or(std::string());
        }
        if (!m_[key].is_string()) {
            refuse(std::string("\"") + key + "\" = " + shown(m_[key]) + " must be a string");
            return fallback.value_or(std::string());
        }
        return m_[key].get<std::string>();
    }

private:
    const nlohmann::json& m_;
    std::string refusal_;
};

namespace {

/// Milliseconds (checked >= 0 by the caller) as a time, rounded to the kernel's 1 ps resolution.
sc_time ms_time(double ms) { return ps(static_cast<std::uint64_t>(std::llround(ms * 1e9))); }

std::optional<FaultKind> fault_kind(const std::string& k) {
    if (k == "flip_data_bit") return FaultKind::flip_data_bit;
    if (k == "flip_cell") return FaultKind::flip_cell;
    if (k == "drop") return FaultKind::drop;
    if (k == "corrupt_stop") return FaultKind::corrupt_stop;
    return std::nullopt;
}

} // namespace


std::string printable_frame_data(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size() && out.size() < 64; ++i) {
        const auto c = static_cast<unsigned char>(s[i]);
        if (c >= 0x20 && c < 0x7F && c != '\\') out += static_cast<char>(c);
        else out += "\\x" + hex(c, 2);
    }
    if (out.size() >= 64) out += "...";
    return out;
}

// ---------------------------------------------------------------------------------------------

BoardMonitor::BoardMonitor(World& world, const MonitorOptions& opt, std::ostream& log, bool http)
    : world_(world), log_(log), commands_(opt.commands), end_(kLongestRun) {
    if (http) server_ = std::make_unique<MonitorServer>(opt.host, opt.port, kMonitorPage, log);
    if (!world_.pacer) {
        world_.pacer = std::make_unique<RealtimePacer>("monitor_pacer", 1.0);
        world_.pacer->set_rtf(0);
    }
    rtf_target_ = world_.pacer->rtf();
    hook_bench();
    wall0_ = rtf_base_wall_ = Clock::now();
}

// The main CPU's last frame per port; the world's own listeners keep running first.
void BoardMonitor::hook_bench() {
    auto keep = [](std::array<LastFrame, World::kPorts>& last, const FrameRecord& f) {
        if (f.port >= World::kPorts) return;
        last[f.port] = {true, f.time.to_seconds(), f.token, f.data, f.bch};
    };
    auto prev_rx = world_.ctl.main.on_received;
    world_.ctl.main.on_received = [this, prev_rx, keep](const FrameRecord& f) {
        if (prev_rx) prev_rx(f);
        keep(last_rx_, f);
    };
    auto prev_tx = world_.ctl.main.on_sent;
    world_.ctl.main.on_sent = [this, prev_tx, keep](const FrameRecord& f) {
        if (prev_tx) prev_tx(f);
        keep(last_tx_, f);
    };
}

bool BoardMonitor::run_until(const sc_time& end) {
    end_ = std::min(end, kLongestRun);
    end_reason_ = end <= kLongestRun ? "the scenario's end (duration_s)" : "the one-hour cap on a run";
    for (;;) {
        serve();
        if (host_ended_) return true;
        if (stop_signal() != 0) return false;
        const sc_time now = sc_core::sc_time_stamp();
        if (now >= end_) return false; // reached by running or by a step
        if (paused_) {
            if (server_) server_->wait_for_request(std::chrono::milliseconds(10));
            else std::this_thread::sleep_for(std::chrono::milliseconds(10));
            continue;
        }
        if (!advance(end_ - now)) return true;
    }
}

// One slice of at most `most`, cut short where a scripted command or (running) a simulated-time
// subscription is due; adapts the slice to 2..8 ms of wall time. False: a host ended the session.
bool BoardMonitor::advance(const sc_time& most) {
    const sc_time now = sc_core::sc_time_stamp();
    sc_time run = std::min(slice_, most);
    if (next_command_ < commands_.size() && commands_[next_command_].at > now)
        run = std::min(run, commands_[next_command_].at - now);
    if (!paused_)
        for (const auto& [id, s] : subs_)
            if (s.sim_clock && s.next_sim > now) run = std::min(run, s.next_sim - now);
    const auto w0 = Clock::now();
    world_.start_for(run);
    const auto wall = Clock::now() - w0;
    if (sc_core::sc_time_stamp() < now + run && stop_signal() == 0) { // sc_pause
        host_ended_ = true;
        return false;
    }
    if (wall < std::chrono::milliseconds(2)) slice_ = std::min(slice_ * 2, kMaxSlice);
    else if (wall > std::chrono::milliseconds(8)) slice_ = std::max(slice_ / 2, kMinSlice);
    return true;
}

// Between two slices: requests first (they may pause), then scripted commands, then updates.
void BoardMonitor::serve() {
    if (server_)
        for (const MonitorServer::Request& r : server_->take_requests()) handle(r.client, r.message);
    if (between_slices_) between_slices_();
    run_due_commands();
    update_rates();
    send_updates();
}

void BoardMonitor::run_due_commands() {
    const sc_time now = sc_core::sc_time_stamp();
    for (; next_command_ < commands_.size() && commands_[next_command_].at <= now; ++next_command_) {
        const ScriptedCommand& c = commands_[next_command_];
        const Outcome o = world_.ctl.main.execute_local(c.token, c.data);
        log_ << "monitor: at " << now.to_seconds() * 1e3 << " ms: " << c.token << " " << c.data << " -> BCH "
             << static_cast<unsigned>(o.bch) << (o.note.empty() ? "" : " (" + o.note + ")") << std::endl;
    }
}

void BoardMonitor::handle(std::uint64_t client, const nlohmann::json& m) {
    const std::string op = m["op"].get<std::string>();
    if (client == 0) { // from the server: a client is gone
        if (op == "closed") subs_.erase(m.value("client", std::uint64_t{0}));
        return;
    }
    Args args(m);
    nlohmann::json out;
    try {
        out = execute(client, op, args);
    } catch (const std::invalid_argument& e) { // refused by a model (a frame it cannot encode, ...)
        args.refuse(e.what());
    }
    if (args.ok()) out["type"] = op == "snapshot" ? "snapshot" : "ok";
    else out = {{"type", "error"}, {"error", args.refusal()}};
    out["op"] = op;
    if (m.contains("id")) out["id"] = m["id"];
    reply(client, std::move(out));
}

void BoardMonitor::reply(std::uint64_t client, nlohmann::json msg) {
    msg["api"] = kApiVersion;
    server_->send(client, std::make_shared<const std::string>(msg.dump()));
}

// One request; returns the reply's fields, or refuses it through `a` (and then changes nothing:
// every argument is read and checked before the request acts).
nlohmann::json BoardMonitor::execute(std::uint64_t client, const std::string& op, Args& a) {
    if (op == "snapshot") return {{"data", snapshot()}};
    if (op == "subscribe") {
        const std::string clock = a.string("clock", std::string("wall"));
        if (a.ok() && clock != "wall" && clock != "sim")
            return a.refuse("\"clock\" = " + Args::shown(clock) + " must be \"wall\" or \"sim\"");
        const double period = a.number("period_ms", clock == "sim" ? 0.01 : 10, 60'000, 100.0);
        const bool path = a.boolean("path", true);
        if (!a.ok()) return {};
        Subscription s;
        s.sim_clock = clock == "sim";
        s.sim_period = ms_time(period);
        s.next_sim = sc_core::sc_time_stamp();
        s.wall_period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(period));
        s.next_wall = Clock::now();
        if (!path) s.path_sent = SIZE_MAX;
        subs_[client] = s;
        return {{"clock", clock}, {"period_ms", period}};
    }
    if (op == "unsubscribe") {
        subs_.erase(client);
        return nlohmann::json::object();
    }
    if (op == "pause") {
        pause();
        return {{"sim_time_s", sc_core::sc_time_stamp().to_seconds()}};
    }
    if (op == "resume") {
        resume();
        return {{"sim_time_s", sc_core::sc_time_stamp().to_seconds()}};
    }
    if (op == "step") {
        const double ms = a.number("ms", 0.001, kMaxStepMs);
        if (!a.ok()) return {};
        const StepResult r = step(ms_time(ms));
        nlohmann::json out = {{"sim_time_s", r.at.to_seconds()}, {"at_end", r.at_end}};
        if (r.at_end) out["note"] = "stopped at " + end_reason_ + ": the run ends";
        return out;
    }
    if (op == "set_rtf") {
        const double rtf = a.number("rtf", 0, 1e6);
        if (!a.ok()) return {};
        if (rtf > 0 && rtf < 0.01) return a.refuse("\"rtf\" must be 0 (as fast as possible) or in [0.01, 1e6]");
        world_.pacer->set_rtf(rtf);
        rtf_target_ = rtf;
        return {{"rtf", rtf}};
    }
    if (op == "motion") {
        const std::string token = a.string("token");
        if (a.ok() && token.size() != 2)
            return a.refuse("\"token\" = " + Args::shown(token) + " must be two characters (docs/system.md §7)");
        const std::string data = a.string("data", std::string());
        if (!a.ok()) return {};
        const Outcome o = motion(token, data);
        return {{"bch", o.bch}, {"data", o.data}, {"note", o.note}};
    }
    if (op != "send_frame" && op != "inject_fault") return a.refuse("unknown op '" + op + "' (docs/monitor.md)");
    const auto port = static_cast<unsigned>(a.integer("port", 0, World::kPorts - 1, 0));
    if (!a.ok()) return {};
    if (op == "send_frame") {
        if (!world_.protocol[port]) return a.refuse("port " + std::to_string(port) + " has no protocol host to send as");
        const std::string token = a.string("token");
        if (a.ok() && token.size() != 2)
            return a.refuse("\"token\" = " + Args::shown(token) + " must be two characters (docs/system.md §7)");
        const std::string data = a.string("data", std::string());
        if (!a.ok()) return {};
        // The host's queue is bounded here: a client flooding frames would grow it without end.
        if (world_.protocol[port]->queued() >= kMaxQueuedFrames)
            return a.refuse("port " + std::to_string(port) + "'s host already has " + std::to_string(kMaxQueuedFrames) +
                            " commands queued; send more once they went out");
        world_.protocol[port]->send(proto::Frame{token, 0, data});
        return {{"port", port}};
    }
    // inject_fault
    const std::string from = a.string("from", std::string("host"));
    if (a.ok() && from != "host" && from != "controller")
        return a.refuse("\"from\" = " + Args::shown(from) + " must be \"host\" or \"controller\"");
    const auto side = from == "host" ? SerialLine::b : SerialLine::a;
    const std::string kind = a.string("kind");
    if (!a.ok()) return {};
    SerialLine& line = world_.lines[port];
    if (kind == "break") {
        const double ms = a.number("duration_ms", 0.001, 10'000, 5.0);
        if (!a.ok()) return {};
        world_.inject_break(port, side, ms_time(ms)); // a cause of expected drops (world.h)
        return {{"port", port}};
    }
    const std::optional<FaultKind> fault = fault_kind(kind);
    if (!fault) return a.refuse("\"kind\" '" + kind + "' is not flip_data_bit, flip_cell, drop, corrupt_stop or break");
    // The side's character as the line will carry it: the host's format, or the 82510's as the
    // firmware programmed it. A bit beyond it would be an error inside the simulation.
    const SerialFormat fmt = side == SerialLine::a ? world_.ctl.comm.uart[port].tx_format()
                                                   : world_.scenario().ports[port].format();
    const bool cell = *fault == FaultKind::flip_cell;
    const unsigned limit = cell ? fmt.cells() + 1 : fmt.data_bits; // cells through the first STOP
    const bool needs_bit = cell || *fault == FaultKind::flip_data_bit;
    if (!needs_bit && a.json().contains("bit")) return a.refuse("\"bit\" applies to flip_data_bit and flip_cell, not " + kind);
    const auto bit = static_cast<unsigned>(a.integer("bit", 0, needs_bit ? limit - 1 : 0, 0));
    if (!a.ok()) {
        a.amend(std::string(" (") + (cell ? "a cell" : "a data bit") + " of a " + fmt.describe() + " character sent by the " +
                from + ")");
        return {};
    }
    // Bounded as the frames are: on an idle side every fault waits for the same next character,
    // and a client injecting in a loop would grow the line's list without end.
    if (line.pending_faults(side) >= kMaxPendingFaults)
        return a.refuse("port " + std::to_string(port) + "'s line already has " + std::to_string(kMaxPendingFaults) +
                        " faults waiting for characters from the " + from + "; inject more once they went out");
    const std::uint64_t index = line.next_index(side);
    line.inject(side, index, *fault, bit);
    return {{"port", port}, {"index", index}};
}

bool BoardMonitor::pause(bool announce) {
    const bool was_running = !paused_;
    if (was_running && announce) log_ << "monitor: paused at " << sc_core::sc_time_stamp().to_seconds() << " s" << std::endl;
    paused_ = true;
    return was_running;
}

Outcome BoardMonitor::motion(const std::string& token, const std::string& data) {
    return world_.ctl.main.execute_local(token, data);
}

// Stepping runs unpaced (as a debugger's step does) and leaves the run paused. It runs in the
// monitor's slices so that what the clients read stays fresh (a 60 s step takes minutes of wall
// time), but takes no request meanwhile: they wait, in order, for the step's end.
BoardMonitor::StepResult BoardMonitor::step(const sc_time& t, const char* who) {
    paused_ = true;
    const sc_time from = sc_core::sc_time_stamp();
    const sc_time asked = from + t, target = std::min(asked, end_);
    world_.pacer->set_rtf(0);
    while (sc_core::sc_time_stamp() < target && stop_signal() == 0) {
        if (!advance(target - sc_core::sc_time_stamp())) break;
        run_due_commands();
        update_rates();
        send_updates();
        if (while_stepping_) while_stepping_();
    }
    world_.pacer->set_rtf(rtf_target_);
    const StepResult r{sc_core::sc_time_stamp(), asked > end_ && sc_core::sc_time_stamp() >= end_};
    if (r.at_end && !end_announced_) {
        log_ << who << ": a step of " << t.to_seconds() * 1e3 << " ms from " << from.to_seconds() << " s stopped at "
             << r.at.to_seconds() << " s, " << end_reason_ << "; the run ends there" << std::endl;
        end_announced_ = true;
    }
    return r;
}

bool BoardMonitor::resume(bool announce) {
    const bool was_paused = paused_;
    if (was_paused && announce) log_ << "monitor: resumed at " << sc_core::sc_time_stamp().to_seconds() << " s" << std::endl;
    paused_ = false;
    world_.pacer->rebase(); // wall time went on while simulated time stood still
    rtf_base_wall_ = Clock::now();
    rtf_base_sim_ = sc_core::sc_time_stamp();
    return was_paused;
}

// Interrupt rates over windows of at least 100 ms simulated; RTF over 0.5 s of running wall time.
void BoardMonitor::update_rates() {
    const sc_time now = sc_core::sc_time_stamp();
    const double dt = (now - rate_base_sim_).to_seconds();
    if (dt >= 0.1) {
        for (unsigned l = 0; l < kIrqLevels; ++l) {
            const std::uint64_t c = world_.probe.count(l);
            irq_rate_hz_[l] = static_cast<double>(c - irq_base_[l]) / dt;
            irq_base_[l] = c;
        }
        rate_base_sim_ = now;
    }
    const auto wall_now = Clock::now();
    const double wall = std::chrono::duration<double>(wall_now - rtf_base_wall_).count();
    if (paused_) {
        rtf_measured_ = 0;
        rtf_base_wall_ = wall_now;
        rtf_base_sim_ = now;
    } else if (wall >= 0.5) {
        rtf_measured_ = (now - rtf_base_sim_).to_seconds() / wall;
        rtf_base_wall_ = wall_now;
        rtf_base_sim_ = now;
    }
}

void BoardMonitor::send_updates() {
    const sc_time now = sc_core::sc_time_stamp();
    const auto wall_now = Clock::now();
    std::shared_ptr<const std::string> base;
    nlohmann::json snap;
    auto base_text = [&]() -> const std::string& {
        if (!base) {
            snap = snapshot();
            base = std::make_shared<const std::string>(snap.dump());
        }
        return *base;
    };
    for (auto& [id, s] : subs_) {
        const bool due = s.sim_clock ? now >= s.next_sim && !paused_ : wall_now >= s.next_wall;
        if (!due) continue;
        if (s.sim_clock) s.next_sim = now + s.sim_period;
        else s.next_wall = std::max(s.next_wall + s.wall_period, wall_now);
        std::string msg = "{\"type\":\"update\",\"api\":" + std::to_string(kApiVersion) + ",\"data\":" + base_text();
        if (s.path_sent != SIZE_MAX) msg += ",\"path\":" + path_json(s, kMaxPathPoints);
        msg += "}";
        server_->send(id, std::make_shared<const std::string>(std::move(msg)));
    }
    if (server_ && wall_now - last_publish_ >= kPublishEvery) {
        base_text();
        server_->publish_snapshot(base);
        last_publish_ = wall_now;
    }
}

// The trajectory samples this client has not had, skipping those where no axis moved:
// {"from": index of the first, "points": [[t_s, x_cmd, y_cmd, x_act, y_act], ...]}. The recorder
// keeps the latest TrajectoryRecorder::kRecent samples: a client further behind resumes at the
// oldest of them ("from" says where).
std::string BoardMonitor::path_json(Subscription& s, std::size_t max_points) {
    nlohmann::json pts = nlohmann::json::array();
    if (world_.motion) {
        const motion::TrajectoryRecorder& rec = world_.motion->recorder();
        const auto& recent = rec.recent();
        s.path_sent = std::max<std::size_t>(s.path_sent, rec.recent_first());
        const std::size_t from = s.path_sent;
        for (std::size_t i = s.path_sent; i < rec.count() && pts.size() < max_points; ++i) {
            const std::size_t r = i - rec.recent_first();
            const auto& a = recent[r];
            const bool moved = r == 0 || a.cmd[0] != recent[r - 1].cmd[0] || a.cmd[1] != recent[r - 1].cmd[1] ||
                               a.act[0] != recent[r - 1].act[0] || a.act[1] != recent[r - 1].act[1];
            if (moved) pts.push_back({a.t_s, a.cmd[0], a.cmd[1], a.act[0], a.act[1]});
            s.path_sent = i + 1;
        }
        return nlohmann::json{{"from", from}, {"points", pts}}.dump();
    }
    return nlohmann::json{{"from", s.path_sent}, {"points", pts}}.dump();
}

} // namespace rcsim::monitor
