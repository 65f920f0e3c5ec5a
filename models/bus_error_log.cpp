// rcsim — the log of bus cycles nothing answered. See bus_error_log.h.
#include "models/bus_error_log.h"

#include "models/clock.h"
#include "models/plumbing/hex.h"

#include <string>

namespace rcsim {

void BusErrorLog::add(Kind kind, std::uint32_t address, BusCycle cycle, const sc_core::sc_time& time) {
    ++counts_[static_cast<std::size_t>(kind)];
    if (first_.size() < kFirst) first_.push_back({kind, address, cycle, time});
}

const char* to_string(BusErrorLog::Kind kind) {
    switch (kind) {
    case BusErrorLog::Kind::unmapped: return "unmapped";
    case BusErrorLog::Kind::rom_write: return "rom_write";
    case BusErrorLog::Kind::tlm_error: return "tlm_error";
    }
    return "?";
}

nlohmann::json to_json(const BusErrorLog& log) {
    using Kind = BusErrorLog::Kind;
    nlohmann::json first = nlohmann::json::array();
    for (const auto& r : log.first()) {
        // I/O ports are 16 bits, memory addresses 20: four or five hex digits.
        const std::string address = "0x" + hex(r.address, is_io(r.cycle) ? 4 : 5);
        first.push_back({{"kind", to_string(r.kind)}, {"address", address}, {"cycle", to_string(r.cycle)},
                         {"time_us", to_us(r.time)}});
    }
    return {{"total", log.total()},
            {"unmapped", log.count(Kind::unmapped)},
            {"rom_write", log.count(Kind::rom_write)},
            {"tlm_error", log.count(Kind::tlm_error)},
            {"first", first}};
}

} // namespace rcsim
