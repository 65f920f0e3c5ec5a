// rcsim — the interrupt log of a run: every completed interrupt as a row, written to
// interrupts.csv as the probe completes it (raw data for the user's own tools, one row per
// interrupt in entry order), and what report.html keeps of the rows: the histograms' sample sets
// and the rows of its two timeline windows. Nothing here grows with the length of the run.
//
// The log is the world's interrupt sink (board/interrupt_probe.h): the runner hands it to the
// world, which tells it every record with its rs232_rx classification. The functions on whole
// row lists below are the same definitions for tests and small tools.
#pragma once

#include "scenarios/board/interrupt_probe.h"
#include "models/stats.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <queue>
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
    bool startup = false;   // requested during the firmware's start-up (InterruptRecord::startup)
    std::uint64_t dpram_reads = 0, dpram_writes = 0;
    std::uint32_t handler = 0;

    // Differences of the exact picosecond times, so that they are the probe's figures to the bit
    // (a difference of the two rounded doubles is not) and repeat as often as those do.
    double latency_us() const { return difference_us(first_isr_us, ir_rise_us); } // only when has_rise
    double service_us() const { return difference_us(iret_done_us, first_isr_us); }
    /// a - b of two times in microseconds, taken in whole picoseconds.
    static double difference_us(double a, double b) {
        return static_cast<double>(std::llround(a * 1e6) - std::llround(b * 1e6)) / 1e6;
    }
    /// Where the interrupt starts on a timeline: IR rise, or the first INTA without a rise.
    double start_us() const { return has_rise ? ir_rise_us : inta1_us; }
};

InterruptRow row_of(const InterruptRecord& r, bool rx);
/// Sorts rows into entry order (first INTA), stable.
void sort_rows(std::vector<InterruptRow>& rows);

/// interrupts.csv: header line, then one line per row. Empty fields for ir_rise/latency without a
/// rise and for eoi without an EOI.
void write_interrupts_csv(const std::vector<InterruptRow>& rows, std::ostream& os);
void write_csv_header(std::ostream& os);
void write_csv_row(const InterruptRow& r, std::ostream& os);

/// A window [start_us, start_us + width) of the timeline.
struct TimeWindow {
    double start_us = 0, end_us = 0;
    std::size_t interrupts = 0; // rows starting inside it
};
/// The window of `width_us` that holds the most interrupt starts (start_us()), beginning at an
/// interrupt start; ties go to the earliest. Rows must be sorted (sort_rows).
TimeWindow busiest_window(const std::vector<InterruptRow>& rows, double width_us);

/// A row as a timeline draws it: nested = entered while an earlier interrupt's handler was still
/// running (that one returns after this one), from the times alone.
struct TimelineRow {
    InterruptRow row;
    bool nested = false;
};
/// The rows of an interrupts.csv (in entry order, as written) that reach into [t0_us, t1_us], each
/// with its nesting as the whole file tells it; the file is read once and only those rows kept.
/// None when the file cannot be read.
std::vector<TimelineRow> csv_rows_around(const std::filesystem::path& csv, double t0_us, double t1_us);

/// The two timelines of report.html, found online from rows given in entry order:
///   the busiest window: busiest_window() over all rows;
///   the zoom: around the row of the longest latency after start-up (the first in entry order of
///   those; without any such row, the first row), wide enough to hold it.
/// Each keeps the rows drawn in it. Besides those it holds the starts not yet in order and the rows
/// that may still fall into a later candidate window: those ending after the earliest start of a
/// busiest window still to be counted, or within keep_us = max(window_us, 2.5 zoom_us) before
/// the settled horizon. The zoom's rows are complete whenever the zoomed interrupt's INTA-to-IRET
/// span is at most 2 keep_us (a zoom reaches back half of that span).
class TimelineWindows {
public:
    explicit TimelineWindows(double window_us = 20000, double zoom_us = 1000);

    /// The next row in entry order.
    void add(const InterruptRow& r);
    /// No row added from now on starts before `horizon_us`.
    void settled(double horizon_us);
    /// No more rows.
    void finish();

    std::uint64_t rows() const { return rows_; }
    /// IR rows drawn: 4, or more when a higher level was seen.
    unsigned levels() const { return levels_; }
    double window_us() const { return window_us_; }
    const TimeWindow& busiest() const { return best_; }
    const std::vector<TimelineRow>& busiest_rows() const { return best_rows_; }
    /// The zoomed row (only when rows() > 0) and the zoom [start, start + width].
    const InterruptRow& worst() const { return worst_; }
    double zoom_start_us() const { return z0_; }
    double zoom_width_us() const { return zoom_; }
    const std::vector<TimelineRow>& zoom_rows() const { return zoom_rows_; }
    /// Rows and starts held for windows still to be decided (the memory it needs).
    std::size_t held() const { return recent_.size() + unordered_starts_.size() + starts_.size(); }

private:
    double window_us_, zoom_us_, keep_us_;
    std::uint64_t rows_ = 0;
    unsigned levels_ = 4;
    double open_until_ = -1; // the latest IRET of the rows so far
    std::deque<TimelineRow> recent_; // entry order
    std::priority_queue<double, std::vector<double>, std::greater<double>> unordered_starts_;
    std::deque<double> starts_; // in order, from the first window start not yet counted
    bool counted_any_ = false;
    double last_counted_ = 0;
    TimeWindow best_;
    std::vector<TimelineRow> best_rows_;
    bool worst_judged_ = false;
    InterruptRow worst_;
    double z0_ = 0, zoom_ = 0;
    std::vector<TimelineRow> zoom_rows_;

    void next_start(double start);
    void count_first_window();
    void choose_zoom(const InterruptRow& r);
};

/// What a run keeps of its interrupt rows: interrupts.csv as it goes, the histograms and the
/// timeline windows of report.html.
class InterruptLog : public InterruptSink {
public:
    explicit InterruptLog(double window_us = 20000, double zoom_us = 1000);

    /// Writes the CSV header to `os` now and every row as it is added; nullptr: no CSV.
    void write_csv_to(std::ostream* os);
    void add(const InterruptRow& r); // entry order
    void settled(double horizon_us) { timeline_.settled(horizon_us); }

    // The world's records as rows (InterruptSink).
    void record(const InterruptRecord& r, bool rx) override { add(row_of(r, rx)); }
    void settle(const sc_core::sc_time& horizon) override { settled(exact_us(horizon)); }
    void finish() override { timeline_.finish(); }

    std::uint64_t rows() const { return timeline_.rows(); }
    /// Histogram k: IR0..IR3 by level, 4 = rs232_rx. Latency only of rows with an IR rise.
    static constexpr unsigned kHistograms = 5;
    const Samples& latency(unsigned k) const { return latency_[k]; }
    const Samples& service(unsigned k) const { return service_[k]; }
    const TimelineWindows& timeline() const { return timeline_; }

private:
    std::ostream* csv_ = nullptr;
    std::array<Samples, kHistograms> latency_, service_;
    TimelineWindows timeline_;
};

} // namespace rcsim::report
