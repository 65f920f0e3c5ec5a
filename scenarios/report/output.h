// rcsim — the files a run writes: its output directory, report.json, the VCD trace. Every failure
// to create or write one is bad input naming the file (exit 2), never a silently missing file.
#pragma once

#include <systemc>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace rcsim {

/// Creates --out DIR before the run, so that a bad path fails at once and not after the simulation.
void prepare_out_dir(const std::string& dir);

/// Writes DIR/report.json.
void write_report_json(const std::filesystem::path& dir, const nlohmann::json& report);

/// SystemC appends ".vcd" to the name it is given: --vcd x.vcd writes x.vcd (not x.vcd.vcd), --vcd x
/// writes x.vcd.
sc_core::sc_trace_file* open_vcd(const std::string& path);

} // namespace rcsim
