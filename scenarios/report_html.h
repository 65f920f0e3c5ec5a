// rcsim — the files `rcsim run` writes beside report.json for a communication scenario:
//
//   interrupts.csv  one row per completed interrupt (the InterruptProbe records, in entry order),
//                   raw data for the user's own tools;
//   report.html     one self-contained page (inline CSS and SVG, no script, no network): header,
//                   checks, Table 3 against the paper, latency/service histograms per source, a
//                   logic-analyser timeline of the busiest window and of the worst latency,
//                   per-port table, main-CPU jitter, and trajectory.svg when the run has motion.
//
// Both are pure functions of their inputs (fixed number formatting, no clock, no host path), so
// two --reproducible runs of the same scenario, seed and ROM give byte-identical files.
#pragma once

#include "scenarios/interrupt_probe.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace rcsim::report {

/// One completed interrupt, times in microseconds of simulated time.
struct InterruptRow {
    std::string source; // rs232_0..rs232_2 (IR0..IR2), dpram (IR3), irN otherwise
    unsigned level = 0;
    unsigned vector = 0;
    double ir_rise_us = 0, inta1_us = 0, inta2_us = 0, first_isr_us = 0, eoi_us = 0, iret_done_us = 0;
    bool has_rise = false, has_eoi = false;
    unsigned depth = 0;     // nesting depth at entry (0 = interrupted the main program)
    bool rx = false;        // an RS-232 interrupt that took a character out of the RX FIFO
    std::uint64_t dpram_reads = 0, dpram_writes = 0;
    std::uint32_t handler = 0;

    double latency_us() const { return first_isr_us - ir_rise_us; } // only when has_rise
    double service_us() const { return iret_done_us - first_isr_us; }
    /// Where the interrupt starts on a timeline: IR rise, or the first INTA without a rise.
    double start_us() const { return has_rise ? ir_rise_us : inta1_us; }
};

/// The source name of an 8259A level on the communication board.
std::string source_name(unsigned level);
InterruptRow row_of(const InterruptRecord& r, bool rx);
/// Sorts rows into entry order (first INTA), stable.
void sort_rows(std::vector<InterruptRow>& rows);

/// interrupts.csv: header line, then one line per row. Empty fields for ir_rise/latency without a
/// rise and for eoi without an EOI.
void write_interrupts_csv(const std::vector<InterruptRow>& rows, std::ostream& os);

/// Equal-width bins [lo + i*width, lo + (i+1)*width); every sample falls into exactly one bin.
struct Histogram {
    double lo = 0, width = 1;
    std::vector<std::uint64_t> counts;
    std::uint64_t total() const;
    double hi() const { return lo + width * static_cast<double>(counts.size()); }
};
/// Bin width 1, 2 or 5 x 10^k giving at most about `target_bins` bins over [min, max].
Histogram make_histogram(const std::vector<double>& samples, unsigned target_bins = 30);

/// A window [start_us, start_us + width) of the timeline.
struct TimeWindow {
    double start_us = 0, end_us = 0;
    std::size_t interrupts = 0; // rows starting inside it
};
/// The window of `width_us` that holds the most interrupt starts (start_us()), beginning at an
/// interrupt start; ties go to the earliest. Rows must be sorted (sort_rows).
TimeWindow busiest_window(const std::vector<InterruptRow>& rows, double width_us);

struct HtmlOptions {
    double window_us = 20000;   // the busiest-window timeline
    double zoom_us = 1000;      // the zoom around the worst latency (widened to hold it)
    std::string trajectory_svg; // trajectory.svg's text, "" = none
};

/// The whole report.html page for `report` (report.json's content) and the probe rows.
std::string render_html(const nlohmann::json& report, const std::vector<InterruptRow>& rows,
                        const HtmlOptions& options = {});

/// Writes dir/interrupts.csv and dir/report.html (embedding dir/trajectory.svg when the report has
/// a motion section and the file exists). Throws std::runtime_error naming a file it cannot write.
void write_report_files(const std::filesystem::path& dir, const nlohmann::json& report,
                        std::vector<InterruptRow> rows);

} // namespace rcsim::report
