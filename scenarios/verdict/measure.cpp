#include "scenarios/verdict/measure.h"

#include "scenarios/world/world.h"

#include <algorithm>

namespace rcsim {

namespace {
using sc_core::sc_time;
constexpr unsigned kPorts = World::kPorts;
} // namespace

nlohmann::json samples_json(const Samples& s) {
    nlohmann::json j = to_json(s.summary());
    // No sample, no figure: null, never a 0 that reads as a measured value.
    if (s.count() == 0)
        for (const char* k : {"min", "mean", "p50", "p99", "max"}) j[k] = nullptr;
    return j;
}

// ---------------------------------------------------------------------------------------------
// figures of the finished world

InterruptFigures measure_interrupts(const World& w) {
    InterruptFigures c;
    static const char* names[] = {"rs232_0", "rs232_1", "rs232_2", "dpram"};
    for (unsigned level = 0; level < 4; ++level) {
        nlohmann::json j;
        j["count"] = w.probe.count(level);
        j["latency_us"] = samples_json(w.probe.latency_us(level));
        j["service_us"] = samples_json(w.probe.service_us(level));
        // The part of each service that kept other requests waiting (the rule judges it).
        j["blocking_us"] = samples_json(w.probe.blocking_us(level));
        c.interrupts[names[level]] = j;
    }
    // RS-232 interrupts that took at least one character out of the RX FIFO (the paper's
    // "RS-232 interrupt"; the others are the firmware's timer tick and transmit interrupts).
    c.rs232_rx_service = w.rs232_rx_service_us();
    c.rs232_rx_latency = w.rs232_rx_latency_us();
    c.interrupts["rs232_rx"] = {{"count", c.rs232_rx_service.count()},
                                {"latency_us", samples_json(c.rs232_rx_latency)},
                                {"service_us", samples_json(c.rs232_rx_service)}};
    c.dpram_byte_us = w.dpram_time().per_byte_us();
    c.dpram_bytes = w.dpram_time().bytes();
    c.interrupts["startup"] = startup_json(w.probe);
    return c;
}

nlohmann::json startup_json(const InterruptProbe& probe) {
    const auto enabled = probe.interrupts_enabled();
    nlohmann::json records = nlohmann::json::array();
    for (const InterruptRecord& r : probe.startup_records())
        records.push_back({{"source", source_name(r.level)},
                           {"ir_rise_us", exact_us(r.ir_rise)},
                           {"latency_us", r.latency_us()},
                           {"service_us", r.service_us()}});
    return {{"interrupts_enabled_us", enabled ? nlohmann::json(exact_us(*enabled)) : nlohmann::json(nullptr)},
            {"count", records.size()},
            {"records", records}};
}

double controller_char_us(const World& w, unsigned p) {
    return to_us(w.ctl.comm.uart[p].rx_format().frame_time());
}

double budget_us(const World& w, const Scenario& s) {
    if (s.budget_us > 0) return s.budget_us;
    bool any_active = false;
    for (const auto& p : s.ports) any_active = any_active || p.host != PortScenario::Host::none;
    double rate = 0; // characters per us, all active ports together
    for (unsigned p = 0; p < kPorts; ++p)
        if (!any_active || s.ports[p].host != PortScenario::Host::none) rate += 1.0 / controller_char_us(w, p);
    return 1.0 / rate;
}
nlohmann::json port_json(const World& w, unsigned p) {
    const auto& u = w.ctl.comm.uart[p].stats();
    nlohmann::json j;
    j["host"] = w.host_kind(p);
    j["controller_format"] = w.ctl.comm.uart[p].rx_format().describe();
    if (w.scenario().ports[p].host != PortScenario::Host::none)
        j["host_format"] = w.scenario().ports[p].format().describe();
    std::uint64_t sent = 0, delivered = 0, failed = 0, naks = 0, retries = 0;
    if (const auto& h = w.protocol[p]) {
        const auto& c = h->counters();
        sent = c.frames_sent, delivered = c.frames_delivered, failed = c.frames_failed;
        naks = c.naks, retries = c.retries;
        j["responses_received"] = c.responses_received;
        j["timeouts"] = c.timeouts;
        j["response_timeouts"] = c.response_timeouts;
        j["collisions"] = c.collisions;
        j["delivery_us"] = samples_json(h->delivery_us());
        j["response_us"] = samples_json(h->response_us());
    }
    if (const auto& h = w.raw[p]) {
        j["bytes_sent"] = h->bytes_sent();
        j["bytes_received"] = h->received().size();
    }
    if (const auto& h = w.tcp[p]) {
        const auto c = h->counters();
        j["tcp"] = {{"listen", h->endpoint()},   {"connections", c.connections}, {"bytes_in", c.bytes_in},
                    {"bytes_sent", c.bytes_sent}, {"bytes_received", c.bytes_received}, {"bytes_out", c.bytes_out},
                    {"bytes_buffered", c.bytes_buffered}, {"bytes_dropped", c.bytes_dropped},
                    {"bytes_unsent", h->bytes_unsent()},  {"input_stalls", c.input_stalls}};
        if (w.scenario().ports[p].tcp.telnet) j["tcp"]["breaks_sent"] = c.breaks_sent;
    }
    if (const auto& h = w.pty[p]) {
        const auto c = h->counters();
        j["pty"] = {{"path", h->path()},
                    {"client_format", h->client_format().describe()},
                    {"bytes_in", c.bytes_in},
                    {"bytes_sent", c.bytes_sent},
                    {"breaks_sent", c.breaks_sent},
                    {"bytes_received", c.bytes_received},
                    {"bytes_out", c.bytes_out},
                    {"bytes_dropped", c.bytes_dropped},
                    {"unknown_speed", c.unknown_speed},
                    {"connections", c.connections},
                    {"disconnects", c.disconnects}};
    }
    if (const auto& h = w.replay[p]) {
        const auto& c = h->counters();
        j["replay"] = {{"bytes_sent", c.bytes_sent},         {"bytes_late", c.bytes_late},
                       {"bytes_received", c.bytes_received}, {"out_expected", c.out_expected},
                       {"out_matched", c.out_matched},       {"out_mismatched", c.out_mismatched},
                       {"out_missing", h->out_missing()},   {"first_mismatch", h->first_mismatch()}};
    }
    j["frames_sent"] = sent;
    j["frames_delivered"] = delivered;
    j["frames_failed"] = failed;
    j["naks"] = naks;
    j["retries"] = retries;
    j["overruns"] = u.overruns;
    j["parity_errors"] = u.parity_errors;
    j["framing_errors"] = u.framing_errors;
    j["break_detects"] = u.break_detects;
    j["rx_fifo_high_water"] = u.rx_fifo_high_water;
    j["chars_received"] = u.chars_received;
    j["chars_sent"] = u.chars_sent;
    j["char_latency_us"] = samples_json(w.char_latency_us[p]);
    j["main_cpu_frames_received"] = w.ctl.main.port_stats(p).frames_received;
    j["main_cpu_frames_sent"] = w.ctl.main.port_stats(p).frames_sent;
    j["responses_dropped"] = w.ctl.main.port_stats(p).responses_dropped;
    j["responses_dropped_sent"] = w.ctl.main.port_stats(p).responses_dropped_sent;
    j.update(observer_json(w.observers[p]));
    return j;
}

nlohmann::json observer_json(const LineObserver& o) {
    auto dir = [&o](LineObserver::Dir d) {
        const auto& c = o.counts(d);
        return nlohmann::json{{"enqs", c.enqs},           {"frames_offered", c.frames_offered},
                              {"frames_bad", c.frames_bad}, {"frames_eot", c.frames_eot},
                              {"naks", c.naks},           {"retries", c.retries},
                              {"abandoned", c.abandoned}};
    };
    auto seq = [](const SequenceMatcher::Counts& c, const char* sent, const char* received) {
        return nlohmann::json{{sent, c.sent},           {received, c.received},   {"matched", c.matched},
                              {"lost", c.lost},         {"duplicates", c.duplicates}, {"unexpected", c.unexpected},
                              {"reordered", c.reordered}, {"after_fault", c.after_fault},
                              {"mismatches", c.mismatches()}};
    };
    nlohmann::json responses = seq(o.responses(), "main_cpu_handed", "host_received");
    responses["dropped"] = {{"gave_up", o.responses().dropped_gave_up},
                            {"port_reset", o.responses().dropped_port_reset}};
    nlohmann::json commands = seq(o.commands(), "host_eot", "main_cpu_received");
    add_expected_drops(commands, o.command_books(), LineObserver::host_to_controller);
    add_expected_drops(responses, o.response_books(), LineObserver::controller_to_host);
    return {{"line", {{"host_to_controller", dir(LineObserver::host_to_controller)},
                      {"controller_to_host", dir(LineObserver::controller_to_host)},
                      {"enq_collisions", o.enq_collisions()},
                      {"breaks", o.breaks()}}},
            {"commands", commands},
            {"responses", responses}};
}

const char* direction_name(unsigned d) {
    return d == LineObserver::host_to_controller ? "host_to_controller" : "controller_to_host";
}

nlohmann::json frame_event_json(const FrameEvent& e, unsigned direction) {
    nlohmann::json j = {{"direction", direction_name(direction)}, {"frame", e.frame}, {"time_us", e.time_us}};
    // An expected drop says how it was dropped; a frame that counts, what became of it.
    j[e.expected ? "dropped" : "what"] = kind_name(e.kind);
    if (!e.cause.empty()) {
        j["cause"] = e.cause.what;
        j["cause_us"] = e.cause.time_us;
    }
    // A give-up: the attempts its sender made, those a cause hit, the retries it still owed.
    if (e.attempts) {
        j["attempts"] = e.attempts->made;
        j["hit"] = e.attempts->hit;
        j["owed_retries"] = e.attempts->owed_retries();
    }
    return j;
}

void add_expected_drops(nlohmann::json& book, const SequenceMatcher& m, unsigned direction) {
    book["expected"] = m.counts().expected;
    book["expected_drops"] = nlohmann::json::array();
    for (const FrameEvent& e : m.expected_drops()) book["expected_drops"].push_back(frame_event_json(e, direction));
    book["in_flight"] = m.counts().in_flight;
}

} // namespace rcsim
