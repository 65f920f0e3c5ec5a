// rcsim — the bus cycles that found nothing to answer them: an access no memory or device
// decodes (unmapped), a write into ROM (the board drops it), and a target that answered with a
// TLM error. On the board each one reads as an open bus (0xFF per byte) or changes nothing, so
// firmware that makes one runs on, wrongly and silently; the log makes it visible: a count per
// kind and the first few cycles with address, cycle kind and time (report.json `bus_errors`,
// docs/scenarios.md).
#pragma once

#include "models/bus.h"

#include <nlohmann/json.hpp>
#include <systemc>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rcsim {

class BusErrorLog {
public:
    enum class Kind : std::uint8_t { unmapped, rom_write, tlm_error };
    static constexpr std::size_t kKinds = 3;
    static constexpr std::size_t kFirst = 8; // cycles kept with their address and time

    struct Record {
        Kind kind;
        std::uint32_t address; // physical (memory) or port (I/O) address of the cycle
        BusCycle cycle;
        sc_core::sc_time time; // T1 of the cycle
    };

    void add(Kind kind, std::uint32_t address, BusCycle cycle, const sc_core::sc_time& time);
    std::uint64_t count(Kind kind) const { return counts_[static_cast<std::size_t>(kind)]; }
    std::uint64_t total() const { return counts_[0] + counts_[1] + counts_[2]; }
    /// The first kFirst cycles of any kind, in order.
    const std::vector<Record>& first() const { return first_; }

private:
    std::array<std::uint64_t, kKinds> counts_{};
    std::vector<Record> first_;
};

const char* to_string(BusErrorLog::Kind kind);

/// {"total", "unmapped", "rom_write", "tlm_error", "first": [{"kind", "address" (hex string),
/// "cycle", "time_us"}]}.
nlohmann::json to_json(const BusErrorLog& log);

} // namespace rcsim
