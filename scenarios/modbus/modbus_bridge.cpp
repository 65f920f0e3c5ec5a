// rcsim — the Modbus TCP server's simulation side (see modbus_bridge.h, docs/monitor.md).
#include "scenarios/modbus/modbus_bridge.h"

#include "models/clock.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <sstream>

namespace rcsim::modbus {

namespace {
// Reads are answered from an image at most this old (or made right after a write was taken):
// filling it evaluates every entry of the map.
constexpr auto kPublishEvery = std::chrono::milliseconds(20);
constexpr std::uint16_t kNoResult = 0xFFFF;
} // namespace

WriteLog::WriteLog(std::ostream& out)
    : lines_(out, kLinesPerSecond, std::chrono::seconds(1), [](std::uint64_t n) {
          return "modbus: ... and " + std::to_string(n) + " more writes in that second, not logged (at most " +
                 std::to_string(kLinesPerSecond) + " lines a second)";
      }) {}

ModbusBridge::ModbusBridge(monitor::BoardMonitor& mon, const std::string& host, unsigned port, std::ostream& log)
    : mon_(mon), server_(host, port, log), log_(log), holding_(table_size(Table::holding_register), 0) {
    holding_[address_of("mailbox.result")] = kNoResult;
    holding_[address_of("step_ms")] = 10;
    publish();
    mon_.between_slices([this] { serve(); });
    // A step takes no write (one could step again) but keeps the reads fresh.
    mon_.while_stepping([this] {
        if (std::chrono::steady_clock::now() - last_publish_ >= kPublishEvery) publish();
    });
}

std::string ModbusBridge::now_text() const {
    std::ostringstream os;
    os << sc_core::sc_time_stamp().to_seconds() << " s";
    return os.str();
}

void ModbusBridge::serve() {
    const std::vector<ModbusServer::Write> writes = server_.take_writes(taken_);
    for (const ModbusServer::Write& w : writes) apply(w);
    log_.flush();
    if (!writes.empty() || std::chrono::steady_clock::now() - last_publish_ >= kPublishEvery) publish();
}

void ModbusBridge::apply(const ModbusServer::Write& w) {
    if (w.table == Table::coil) {
        if (w.address == address_of("pause")) {
            if (!w.value) {
                if (mon_.resume(false)) log_.line("resumed at " + now_text());
                release_held();
            } else if (mon_.pause(false)) log_.line("paused at " + now_text());
        } else if (w.address == address_of("step")) {
            if (!w.value) return;
            release_held();
            const unsigned ms = holding_[address_of("step_ms")];
            const std::string from = now_text();
            mon_.step(us(ms * std::uint64_t{1000}), "modbus");
            log_.line("step of " + std::to_string(ms) + " ms: " + from + " -> " + now_text());
        } else act(w); // a servo coil
        return;
    }
    holding_[w.address] = w.value;
    if (w.address == address_of("mailbox.go") && w.value) act(w);
}

void ModbusBridge::act(const ModbusServer::Write& w, bool held) {
    if (mon_.paused() && !held) {
        held_.push_back(w);
        return;
    }
    if (w.table == Table::holding_register) return execute_mailbox();
    const unsigned axis = w.address - address_of("axis{n}.servo_on");
    if (mon_.world().motion) mon_.world().motion->power(axis).Enable = w.value != 0;
}

void ModbusBridge::release_held() {
    std::vector<ModbusServer::Write> held;
    held.swap(held_);
    for (const ModbusServer::Write& w : held) act(w, true);
}

// The mailbox's command as a frame's would be executed: token, then the parameters as its
// decimal data field.
void ModbusBridge::execute_mailbox() {
    const std::uint16_t t = holding_[address_of("mailbox.token")];
    const std::string token{static_cast<char>(t >> 8), static_cast<char>(t & 0xFF)};
    std::string data;
    const unsigned count = holding_[address_of("mailbox.count")];
    for (unsigned i = 0; i < count; ++i) {
        const std::uint16_t at = static_cast<std::uint16_t>(address_of("mailbox.param0") + 2 * i);
        const auto v = static_cast<std::int32_t>(static_cast<std::uint32_t>(holding_[at]) << 16 | holding_[at + 1]);
        data += (i ? "," : "") + std::to_string(v);
    }
    const Outcome o = mon_.motion(token, data);
    // BCH 02 and 05 carry the ErrorID as their data (docs/motion.md).
    const bool numeric = !o.data.empty() && std::all_of(o.data.begin(), o.data.end(), ::isdigit) && o.data.size() < 6;
    holding_[address_of("mailbox.result")] = o.bch;
    holding_[address_of("mailbox.error_id")] =
        (o.bch == 2 || o.bch == 5) && numeric ? static_cast<std::uint16_t>(std::min(65535L, std::atol(o.data.c_str()))) : 0;
    ++holding_[address_of("mailbox.sequence")];
    holding_[address_of("mailbox.go")] = 0;
    std::ostringstream os;
    os << "at " << sc_core::sc_time_stamp().to_seconds() * 1e3 << " ms: mailbox " << token << " " << data << " -> BCH "
       << static_cast<unsigned>(o.bch) << (o.note.empty() ? "" : " (" + o.note + ")");
    log_.line(os.str());
}

void ModbusBridge::publish() {
    ModbusServer::Image im;
    im.coils.assign(table_size(Table::coil), 0);
    im.discrete_inputs.assign(table_size(Table::discrete_input), 0);
    im.input_registers.assign(table_size(Table::input_register), 0);
    im.holding_registers = holding_;
    im.writes_taken = taken_;
    for (const Row& r : map_rows()) {
        const Entry& e = *r.entry;
        if (!e.value) continue;
        const std::vector<std::uint16_t> v = encode(e.type, e.scale, e.value(mon_, r.index));
        if (e.table == Table::coil) im.coils[r.address] = static_cast<std::uint8_t>(v[0]);
        else if (e.table == Table::discrete_input) im.discrete_inputs[r.address] = static_cast<std::uint8_t>(v[0]);
        else std::copy(v.begin(), v.end(), im.input_registers.begin() + r.address);
    }
    // What is held while paused reads as written.
    for (const ModbusServer::Write& w : held_)
        if (w.table == Table::coil) im.coils[w.address] = static_cast<std::uint8_t>(w.value);
    server_.publish(std::move(im));
    last_publish_ = std::chrono::steady_clock::now();
}

} // namespace rcsim::modbus
