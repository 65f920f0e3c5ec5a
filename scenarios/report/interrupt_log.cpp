// rcsim — the interrupt log of a run: interrupts.csv as it goes, and what report.html keeps of the
// rows (the histograms' samples, the two timeline windows). See interrupt_log.h.
#include "scenarios/report/interrupt_log.h"

#include "models/plumbing/gzip_stream.h"
#include "models/plumbing/hex.h"
#include "scenarios/report/svg.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <ostream>
#include <sstream>

namespace rcsim::report {

using svg::num;

// ---------------------------------------------------------------------------------------------
// rows and CSV

InterruptRow row_of(const InterruptRecord& r, bool rx) {
    const auto exact = exact_us;
    InterruptRow row;
    row.source = source_name(r.level);
    row.level = r.level;
    row.vector = r.vector;
    row.ir_rise_us = r.has_rise ? exact(r.ir_rise) : 0;
    row.inta1_us = exact(r.inta1);
    row.inta2_us = exact(r.inta2);
    row.first_isr_us = exact(r.first_isr);
    row.eoi_us = r.has_eoi ? exact(r.eoi) : 0;
    row.iret_done_us = exact(r.iret_done);
    row.has_rise = r.has_rise;
    row.has_eoi = r.has_eoi;
    row.depth = r.depth;
    row.rx = rx;
    row.startup = r.startup;
    row.dpram_reads = r.dpram_reads;
    row.dpram_writes = r.dpram_writes;
    row.handler = r.handler;
    return row;
}

void sort_rows(std::vector<InterruptRow>& rows) {
    std::stable_sort(rows.begin(), rows.end(),
                     [](const InterruptRow& a, const InterruptRow& b) { return a.inta1_us < b.inta1_us; });
}

void write_csv_header(std::ostream& os) {
    os << "source,level,vector,ir_rise_us,inta1_us,inta2_us,first_isr_us,eoi_us,iret_done_us,latency_us,"
          "service_us,depth,rx,dpram_read_bytes,dpram_write_bytes,handler\n";
}

namespace {

/// Appends printf("%.6f", us) for a time in microseconds that came from whole picoseconds
/// (exact_us, InterruptRow::difference_us). Below 2^31 us (about 36 minutes) the double is
/// within 0.25 ps of its picosecond count and us * 1e6 within 0.25 ps more, so the count is
/// llround(us * 1e6) and its digits are the printf digits; beyond that, and for negative
/// values, svg::num formats it. (One row a few hundred instructions instead of thousands: a
/// run writes a row per interrupt.)
void append_us6(std::string& out, double us) {
    if (!(us >= 0 && us < 2147483648.0)) {
        out += num(us, 6);
        return;
    }
    const auto ps = static_cast<unsigned long long>(std::llround(us * 1e6));
    char buf[32];
    char* end = std::to_chars(buf, buf + sizeof buf, ps / 1000000).ptr;
    *end++ = '.';
    const unsigned long long frac = ps % 1000000;
    char digits[8];
    const char* d_end = std::to_chars(digits, digits + sizeof digits, frac).ptr;
    const std::size_t n = static_cast<std::size_t>(d_end - digits);
    for (std::size_t i = n; i < 6; ++i) *end++ = '0';
    for (const char* d = digits; d < d_end; ++d) *end++ = *d;
    out.append(buf, end);
}

template <typename N> void append_int(std::string& out, N v) {
    char buf[24];
    out.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

} // namespace

void write_csv_row(const InterruptRow& r, std::ostream& os) {
    std::string line;
    line.reserve(192);
    line += r.source;
    line += ',';
    append_int(line, r.level);
    line += ',';
    append_int(line, r.vector);
    line += ',';
    if (r.has_rise) append_us6(line, r.ir_rise_us);
    for (double t : {r.inta1_us, r.inta2_us, r.first_isr_us}) {
        line += ',';
        append_us6(line, t);
    }
    line += ',';
    if (r.has_eoi) append_us6(line, r.eoi_us);
    line += ',';
    append_us6(line, r.iret_done_us);
    line += ',';
    if (r.has_rise) append_us6(line, r.latency_us());
    line += ',';
    append_us6(line, r.service_us());
    line += ',';
    append_int(line, r.depth);
    line += r.rx ? ",1," : ",0,";
    append_int(line, r.dpram_reads);
    line += ',';
    append_int(line, r.dpram_writes);
    line += ',';
    // The handler's linear address: five hex digits (20 bits), more if ever wider.
    line += hex(r.handler, 5);
    line += '\n';
    os.write(line.data(), static_cast<std::streamsize>(line.size()));
}

std::vector<TimelineRow> csv_rows_around(const std::filesystem::path& csv, double t0_us, double t1_us) {
    std::vector<TimelineRow> out;
    GzipReader in(csv); // interrupts.csv or interrupts.csv.gz
    std::string line;
    if (!std::getline(in, line)) return out; // the header
    double open_until = -1; // the latest IRET so far: a row ending before it was nested in it
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream ls(line);
        for (std::string cell; std::getline(ls, cell, ',');) f.push_back(cell);
        if (f.size() < 16) continue;
        auto num = [](const std::string& t) { return t.empty() ? 0.0 : std::strtod(t.c_str(), nullptr); };
        InterruptRow r;
        r.source = f[0];
        r.level = static_cast<unsigned>(std::strtoul(f[1].c_str(), nullptr, 10));
        r.vector = static_cast<unsigned>(std::strtoul(f[2].c_str(), nullptr, 10));
        r.has_rise = !f[3].empty();
        r.ir_rise_us = num(f[3]);
        r.inta1_us = num(f[4]);
        r.inta2_us = num(f[5]);
        r.first_isr_us = num(f[6]);
        r.has_eoi = !f[7].empty();
        r.eoi_us = num(f[7]);
        r.iret_done_us = num(f[8]);
        r.depth = static_cast<unsigned>(std::strtoul(f[11].c_str(), nullptr, 10));
        r.rx = f[12] == "1";
        r.handler = static_cast<std::uint32_t>(std::strtoul(f[15].c_str(), nullptr, 16));
        const bool nested = open_until > r.iret_done_us;
        open_until = std::max(open_until, r.iret_done_us);
        if (r.start_us() <= t1_us && r.iret_done_us >= t0_us) out.push_back({r, nested});
    }
    return out;
}

void write_interrupts_csv(const std::vector<InterruptRow>& rows, std::ostream& os) {
    write_csv_header(os);
    for (const InterruptRow& r : rows) write_csv_row(r, os);
}


// ---------------------------------------------------------------------------------------------
// the busiest window

TimeWindow busiest_window(const std::vector<InterruptRow>& rows, double width_us) {
    TimeWindow best;
    std::vector<double> starts;
    starts.reserve(rows.size());
    for (const auto& r : rows) starts.push_back(r.start_us());
    std::sort(starts.begin(), starts.end());
    if (starts.empty()) return best;
    best = {starts[0], starts[0] + width_us, 0};
    std::size_t j = 0;
    for (std::size_t i = 0; i < starts.size(); ++i) {
        if (i > 0 && starts[i] == starts[i - 1]) continue; // same window as the previous start
        if (j < i) j = i;
        while (j < starts.size() && starts[j] < starts[i] + width_us) ++j;
        if (j - i > best.interrupts) best = {starts[i], starts[i] + width_us, j - i};
    }
    return best;
}


// ---------------------------------------------------------------------------------------------
// the online windows and the log

TimelineWindows::TimelineWindows(double window_us, double zoom_us)
    : window_us_(window_us), zoom_us_(zoom_us), keep_us_(std::max(window_us, 2.5 * zoom_us)) {}

namespace {
bool overlaps(const InterruptRow& r, double t0, double t1) { return !(r.iret_done_us < t0 || r.start_us() > t1); }
} // namespace

void TimelineWindows::add(const InterruptRow& r) {
    ++rows_;
    levels_ = std::max(levels_, r.level + 1);
    const bool nested = open_until_ > r.iret_done_us;
    open_until_ = std::max(open_until_, r.iret_done_us);
    recent_.push_back({r, nested});
    unordered_starts_.push(r.start_us());
    // The zoom: the first row of the longest latency so far (start-up rows aside: no check judges
    // them), else the first row.
    const bool judged = r.has_rise && !r.startup;
    if (rows_ == 1 || (judged && (!worst_judged_ || r.latency_us() > worst_.latency_us()))) {
        choose_zoom(r);
    } else if (overlaps(r, z0_, z0_ + zoom_)) {
        zoom_rows_.push_back(recent_.back());
    }
}

void TimelineWindows::choose_zoom(const InterruptRow& r) {
    worst_ = r;
    worst_judged_ = r.has_rise && !r.startup;
    // The whole interrupt when its wait fits, else its entry and service with the IR rise named
    // at the left edge.
    zoom_ = zoom_us_;
    const double whole = (r.iret_done_us - r.start_us()) / 0.85;
    if (whole <= 2.5 * zoom_) {
        zoom_ = std::max(zoom_, whole);
        z0_ = r.start_us() - 0.05 * zoom_;
    } else {
        zoom_ = std::max(zoom_, (r.iret_done_us - r.inta1_us) / 0.6);
        z0_ = r.inta1_us - 0.3 * zoom_;
    }
    z0_ = std::max(0.0, z0_);
    zoom_rows_.clear();
    for (const TimelineRow& t : recent_)
        if (overlaps(t.row, z0_, z0_ + zoom_)) zoom_rows_.push_back(t);
}

void TimelineWindows::settled(double horizon_us) {
    while (!unordered_starts_.empty() && unordered_starts_.top() < horizon_us) {
        next_start(unordered_starts_.top());
        unordered_starts_.pop();
    }
    // A row is needed while it ends at or after the earliest start of a window still to be
    // counted, or while a later zoom may reach back to it.
    double needed_from = horizon_us - keep_us_;
    if (!starts_.empty()) needed_from = std::min(needed_from, starts_.front());
    if (!unordered_starts_.empty()) needed_from = std::min(needed_from, unordered_starts_.top());
    while (!recent_.empty() && recent_.front().row.iret_done_us < needed_from) recent_.pop_front();
}

void TimelineWindows::next_start(double start) {
    starts_.push_back(start);
    // The window from the first start is complete once a start at or past its end is in.
    while (starts_.front() + window_us_ <= start) count_first_window();
}

void TimelineWindows::count_first_window() {
    const double t0 = starts_.front();
    // A repeated start opens the same window with fewer rows after it: never the busiest.
    if (!counted_any_ || t0 != last_counted_) {
        const double t1 = t0 + window_us_;
        const auto n = static_cast<std::size_t>(std::lower_bound(starts_.begin(), starts_.end(), t1) - starts_.begin());
        if (!counted_any_ || n > best_.interrupts) {
            best_ = {t0, t1, n};
            best_rows_.clear();
            for (const TimelineRow& t : recent_)
                if (overlaps(t.row, t0, t1)) best_rows_.push_back(t);
        }
        counted_any_ = true;
        last_counted_ = t0;
    }
    starts_.pop_front();
}

void TimelineWindows::finish() {
    settled(std::numeric_limits<double>::infinity());
    while (!starts_.empty()) count_first_window();
}

InterruptLog::InterruptLog(double window_us, double zoom_us) : timeline_(window_us, zoom_us) {}

void InterruptLog::write_csv_to(std::ostream* os) {
    csv_ = os;
    if (csv_) write_csv_header(*csv_);
}

void InterruptLog::add(const InterruptRow& r) {
    if (csv_) write_csv_row(r, *csv_);
    timeline_.add(r);
    if (r.startup) return; // reported apart (report.json interrupts.startup), not in the histograms
    auto put = [&r](Samples& latency, Samples& service) {
        if (r.has_rise) latency.add(r.latency_us());
        service.add(r.service_us());
    };
    if (r.level < 4) put(latency_[r.level], service_[r.level]);
    if (r.rx) put(latency_[4], service_[4]);
}


} // namespace rcsim::report
