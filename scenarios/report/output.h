// rcsim — the files a run writes: its output directory, report.json, the VCD trace. Every failure
// to create or write one is bad input naming the file (exit 2), never a silently missing file.
#pragma once

#include <systemc>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace rcsim {

/// The files a run writes under fixed names in its folder (report.json, report.html, interrupts.csv,
/// the profile, the trajectory files).
const std::vector<std::string>& run_file_names();

/// Creates --out DIR before the run, so that a bad path fails at once and not after the simulation,
/// and removes the files an earlier run left there under run_file_names(): a reused folder never
/// shows an old profile beside a new report. Other files are left alone.
void prepare_out_dir(const std::string& dir);

/// Creates the folder of each of the run's output files (a relative `log: logs/p0.log` lands in
/// DIR/logs/); throws ConfigError naming the one it cannot create.
void prepare_output_folders(const std::vector<std::string*>& files);

/// Writes DIR/report.json.
void write_report_json(const std::filesystem::path& dir, const nlohmann::json& report);

/// SystemC appends ".vcd" to the name it is given, so it gets `path` without it: x.vcd writes x.vcd
/// (not x.vcd.vcd). `rcsim run --vcd` refuses a name without ".vcd" (/dev/null would become
/// /dev/null.vcd); given one here, x still writes x.vcd.
sc_core::sc_trace_file* open_vcd(const std::string& path);
/// Whether `path` names a file ending in ".vcd" (more than the extension alone).
bool is_vcd_name(const std::string& path);

} // namespace rcsim
