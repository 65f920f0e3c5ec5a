// rcsim — report.html, the page `rcsim run` writes beside report.json: one self-contained page
// (inline CSS and SVG, no script, no network) with the header, the checks, Table 3 against the
// paper, latency/service histograms per source, a logic-analyser timeline of the busiest window
// and of the worst latency, the per-port table, the main CPU's jitter, and trajectory.svg when the
// run has motion; and the page of a motion-only run. Its interrupt figures come from the run's
// InterruptLog (interrupt_log.h), which also writes interrupts.csv.
//
// Pages are pure functions of their inputs (fixed number formatting, no clock, no host path), so
// two --reproducible runs of the same scenario, seed and ROM give byte-identical files.
#pragma once

#include "scenarios/report/interrupt_log.h"
#include "models/stats.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace rcsim::report {

/// Equal-width bins [lo + i*width, lo + (i+1)*width); every sample falls into exactly one bin.
struct Histogram {
    double lo = 0, width = 1;
    std::vector<std::uint64_t> counts;
    std::uint64_t total() const;
    double hi() const { return lo + width * static_cast<double>(counts.size()); }
};
/// Bin width 1, 2 or 5 x 10^k giving at most about `target_bins` bins over [min, max].
Histogram make_histogram(const std::vector<double>& samples, unsigned target_bins = 30);
/// The same over a sample set's kept values (the same bins while it is exact).
Histogram make_histogram(const Samples& samples, unsigned target_bins = 30);

struct HtmlOptions {
    double window_us = 20000;   // the busiest-window timeline (rows version of render_html)
    double zoom_us = 1000;      // the zoom around the worst latency (widened to hold it)
    std::string trajectory_svg; // trajectory.svg's text, "" = none
    std::string flame_svg;      // the cycle profile's flame graph (scenarios/trace/flame_graph.h), "" = none
    std::string trajectory_time_svg; // trajectory_time.svg's text, "" = none
    std::string coverage_html;  // the --coverage section (scenarios/coverage/coverage_run.h), "" = none
    /// The run's interrupts.csv: a failed check with a time ("at_us") gets the interrupt timeline
    /// around it, read back from the file (only the rows in that window are kept). "" = none.
    std::filesystem::path interrupts_csv;
};

/// The whole report.html page for `report` (report.json's content) and the run's interrupt log
/// (finished). The timeline widths are the log's.
std::string render_html(const nlohmann::json& report, const InterruptLog& log, const HtmlOptions& options = {});
/// The same from a list of rows (any order): they go through an InterruptLog with the options'
/// window and zoom widths.
std::string render_html(const nlohmann::json& report, const std::vector<InterruptRow>& rows,
                        const HtmlOptions& options = {});

/// Writes dir/report.html (embedding dir/trajectory.svg and dir/trajectory_time.svg when the
/// report has a motion section and the files exist). Throws std::runtime_error naming a file it
/// cannot write. `flame_svg`: the --profile flame graph for a "Profile" section ("" = none);
/// `coverage_html`: the --coverage section, as it is ("" = none).
void write_report_html(const std::filesystem::path& dir, const nlohmann::json& report, const InterruptLog& log,
                       const std::string& flame_svg = "", const std::string& coverage_html = "");

/// The report.html of a motion-only run (a `motion:` section, docs/motion.md): the banner, the
/// checks, the motion figures and the trajectory pictures.
std::string render_motion_html(const nlohmann::json& report, const HtmlOptions& options);
/// Writes dir/report.html for a motion-only run, with dir's trajectory pictures.
void write_motion_report_html(const std::filesystem::path& dir, const nlohmann::json& report);

} // namespace rcsim::report
