// rcsim tests — counts read back from a report.json.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace rcsim::test {

/// Every completed interrupt of `source` in `report`: its "count" (after start-up) and the
/// start-up interrupts of that source (report.json interrupts.startup, docs/scenarios.md).
inline std::uint64_t completed(const nlohmann::json& report, const std::string& source) {
    std::uint64_t n = report["interrupts"][source]["count"].get<std::uint64_t>();
    for (const auto& r : report["interrupts"]["startup"]["records"]) n += r["source"] == source;
    return n;
}

} // namespace rcsim::test
