// rcsim — interrupts.csv and report.html. See report_html.h.
#include "scenarios/report_html.h"

#include "models/config_error.h"
#include "models/stats.h"
#include "scenarios/svg.h"

#include <algorithm>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace rcsim::report {

using svg::esc;
using svg::num;
using json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// rows and CSV

std::string source_name(unsigned level) {
    if (level < 3) return "rs232_" + std::to_string(level);
    if (level == 3) return "dpram";
    return "ir" + std::to_string(level);
}

double exact_us(const sc_core::sc_time& t) {
    // sc_time is an integer count of picoseconds: value() / 1e6 keeps every digit.
    return sc_core::sc_get_time_resolution() == sc_core::sc_time(1, sc_core::SC_PS)
               ? static_cast<double>(t.value()) / 1e6
               : t.to_seconds() * 1e6;
}

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
    static const char hex[] = "0123456789ABCDEF";
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
    // The handler's linear address, "%05X": five hex digits (20 bits), more if ever wider.
    std::string h;
    for (std::uint32_t v = r.handler; v || h.size() < 5; v >>= 4) h.insert(h.begin(), hex[v & 15]);
    line += h;
    line += '\n';
    os.write(line.data(), static_cast<std::streamsize>(line.size()));
}

void write_interrupts_csv(const std::vector<InterruptRow>& rows, std::ostream& os) {
    write_csv_header(os);
    for (const InterruptRow& r : rows) write_csv_row(r, os);
}

// ---------------------------------------------------------------------------------------------
// histogram and window

std::uint64_t Histogram::total() const {
    std::uint64_t n = 0;
    for (auto c : counts) n += c;
    return n;
}

namespace {
/// Bins over [mn, mx]; then put(x, n) for every value.
Histogram empty_bins(double mn, double mx, unsigned target_bins) {
    Histogram h;
    const double span = mx - mn;
    h.width = span > 0 ? svg::nice_step(span, static_cast<int>(std::max(1u, target_bins))) : 1.0;
    h.lo = std::floor(mn / h.width) * h.width;
    h.counts.assign(static_cast<std::size_t>(std::floor((mx - h.lo) / h.width)) + 1, 0);
    // A last bin that only the rounding of max fills is kept: max must lie inside the bins.
    return h;
}
void put(Histogram& h, double x, std::uint64_t n) {
    auto i = static_cast<long long>(std::floor((x - h.lo) / h.width));
    i = std::clamp<long long>(i, 0, static_cast<long long>(h.counts.size()) - 1);
    h.counts[static_cast<std::size_t>(i)] += n;
}
} // namespace

Histogram make_histogram(const std::vector<double>& v, unsigned target_bins) {
    if (v.empty()) return {};
    const auto [mn, mx] = std::minmax_element(v.begin(), v.end());
    Histogram h = empty_bins(*mn, *mx, target_bins);
    for (double x : v) put(h, x, 1);
    return h;
}

Histogram make_histogram(const Samples& s, unsigned target_bins) {
    const auto& v = s.values();
    if (v.empty()) return {};
    Histogram h = empty_bins(v.front().first, v.back().first, target_bins);
    for (const auto& [x, n] : v) put(h, x, n);
    return h;
}

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
    // The zoom: the first row of the longest latency so far, else the first row.
    if (rows_ == 1 || (r.has_rise && (!worst_has_rise_ || r.latency_us() > worst_.latency_us()))) {
        choose_zoom(r);
    } else if (overlaps(r, z0_, z0_ + zoom_)) {
        zoom_rows_.push_back(recent_.back());
    }
}

void TimelineWindows::choose_zoom(const InterruptRow& r) {
    worst_ = r;
    worst_has_rise_ = r.has_rise;
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
    auto put = [&r](Samples& latency, Samples& service) {
        if (r.has_rise) latency.add(r.latency_us());
        service.add(r.service_us());
    };
    if (r.level < 4) put(latency_[r.level], service_[r.level]);
    if (r.rx) put(latency_[4], service_[4]);
    timeline_.add(r);
}

// ---------------------------------------------------------------------------------------------
// HTML helpers

namespace {

const char* kLevelColour[] = {"#1f77b4", "#2ca02c", "#9467bd", "#e07b00", "#8c564b", "#7f7f7f", "#bcbd22", "#17becf"};
const char* colour_of(unsigned level) { return kLevelColour[level % 8]; }

double jd(const json& j, const char* key, double def = 0) {
    if (j.is_object() && j.contains(key) && j[key].is_number()) return j[key].get<double>();
    return def;
}
std::uint64_t ju(const json& j, const char* key) {
    if (j.is_object() && j.contains(key) && j[key].is_number()) return j[key].get<std::uint64_t>();
    return 0;
}
std::string js(const json& j, const char* key, const std::string& def = "") {
    if (j.is_object() && j.contains(key) && j[key].is_string()) return j[key].get<std::string>();
    return def;
}
const json& jo(const json& j, const char* key) {
    static const json empty = json::object();
    if (j.is_object() && j.contains(key)) return j[key];
    return empty;
}

/// Whole numbers without decimals, others with `dec`.
std::string smart(double v, int dec = 3) {
    return (std::floor(v) == v && std::fabs(v) < 1e15) ? num(v, 0) : num(v, dec);
}

std::string hex(unsigned v, int digits) {
    char b[16];
    std::snprintf(b, sizeof b, "%0*X", digits, v);
    return b;
}

const char* kCss = R"(
body{font-family:-apple-system,"Segoe UI",Helvetica,Arial,sans-serif;font-size:14px;color:#222;margin:0 auto;max-width:1200px;padding:0 16px 40px}
h1{font-size:22px;margin:0}
h2{font-size:18px;border-bottom:2px solid #ddd;padding-bottom:4px;margin-top:34px}
h3{font-size:15px;margin:18px 0 6px}
.banner{display:flex;justify-content:space-between;align-items:center;padding:14px 18px;margin:16px 0 10px;border-radius:6px;color:#fff}
.banner.pass{background:#1e7e34}.banner.fail{background:#c82333}
.interrupted{background:#fff3cd;border:1px solid #e0a800;padding:8px 12px;font-weight:bold}
.verdict{font-size:26px;font-weight:bold;letter-spacing:1px}
table{border-collapse:collapse;margin:6px 0 10px}
th,td{border:1px solid #ccc;padding:3px 7px;text-align:right;white-space:nowrap}
th{background:#f2f2f2;white-space:normal;vertical-align:bottom}
td.l,th.l{text-align:left}
tr.pass td.v{background:#e3f4e6}tr.fail td.v{background:#fbe0e0}
td.bad{background:#fbe0e0;font-weight:bold}
td.ok{color:#1e7e34;font-weight:bold}td.ko{color:#c82333;font-weight:bold}
table.meta td{text-align:left;border:none;padding:1px 14px 1px 0}
table.meta td:first-child{color:#666}
nav a{margin-right:14px}
.grid{display:flex;flex-wrap:wrap;gap:10px}
.grid svg,.chart svg{border:1px solid #e4e4e4;background:#fff}
.note{color:#555;font-size:13px;max-width:1100px}
code{background:#f4f4f4;padding:0 3px}
)";

// ---------------------------------------------------------------------------------------------
// charts

/// A histogram of `v` with min, mean, p99 and max marked.
std::string histogram_svg(const std::string& title, const Samples& v, const std::string& xlabel,
                          const std::string& colour) {
    const double W = 570, H = 260, L = 62, R = 16, T = 48, B = 58;
    svg::Doc d(W, H, title);
    d.text(L, 18, title, "start", 14, "font-weight=\"bold\"");
    if (v.empty()) {
        d.text(W / 2, H / 2, "no samples", "middle", 13, "fill=\"#888\"");
        return d.str();
    }
    const Histogram h = make_histogram(v, 30);
    const Summary st = v.summary();
    std::uint64_t maxc = 0, minnz = ~0ull;
    for (auto c : h.counts) {
        maxc = std::max(maxc, c);
        if (c) minnz = std::min(minnz, c);
    }
    const bool log = maxc >= 100 && maxc >= 20 * minnz;
    d.text(L, 36,
           "n = " + std::to_string(st.count) + "   min " + num(st.min, 1) + "   mean " + num(st.mean, 1) + "   p99 " +
               num(st.p99, 1) + "   max " + num(st.max, 1) + " us   (bin " + smart(h.width, 3) + " us)",
           "start", 11, "fill=\"#444\"");
    svg::Scale sx{h.lo, h.hi(), L, W - R, false};
    svg::Scale sy{log ? 0.5 : 0.0, log ? maxc * 2.0 : std::max(1.0, maxc * 1.12), H - B, T, log};
    d.y_axis(sy, L, W - R, log ? "count (log scale)" : "count", 5);
    for (std::size_t i = 0; i < h.counts.size(); ++i) {
        if (!h.counts[i]) continue;
        const double a = h.lo + h.width * static_cast<double>(i), b = a + h.width;
        const double x0 = sx(a), x1 = sx(b), y = sy(static_cast<double>(h.counts[i]));
        const double gap = (x1 - x0) > 4 ? 1 : 0;
        d.with_title("<rect x=\"" + num(x0 + gap / 2) + "\" y=\"" + num(y) + "\" width=\"" +
                         num(std::max(x1 - x0 - gap, 0.8)) + "\" height=\"" + num(sy.p0 - y) + "\" fill=\"" +
                         colour + "\"",
                     num(a, 3) + " .. " + num(b, 3) + " us: " + std::to_string(h.counts[i]));
    }
    d.x_axis(sx, H - B, xlabel, 8);
    struct M { const char* name; double v; const char* c; };
    const M marks[] = {{"min", st.min, "#555"}, {"mean", st.mean, "#0b4f9c"}, {"p99", st.p99, "#d46b00"},
                       {"max", st.max, "#c82333"}};
    for (int k = 0; k < 4; ++k) {
        const double x = sx(marks[k].v);
        d.line(x, T, x, H - B, marks[k].c, 1.5, "stroke-dasharray=\"4 3\"");
        const bool right = x > W - R - 44;
        d.text(right ? x - 3 : x + 3, T + 11 + 12 * k, marks[k].name, right ? "end" : "start", 11,
               std::string("fill=\"") + marks[k].c + "\"");
    }
    return d.str();
}

/// Table 3: simulated vs paper, bars with the budget line and the margin.
std::string table3_svg(const json& t) {
    const double isr = jd(t, "rs232_isr_us"), dp = jd(t, "dpram_byte_us");
    const double pisr = jd(t, "paper_rs232_isr_us", 82), pdp = jd(t, "paper_dpram_byte_us", 52.553);
    const double budget = jd(t, "budget_us"), margin = jd(t, "margin_us");
    const double W = 760, H = 380, L = 70, R = 170, T = 24, B = 84;
    svg::Doc d(W, H, "Table 3: simulated vs paper");
    const double top = std::max({budget, isr + dp, pisr + pdp, 1.0}) * 1.12;
    svg::Scale sy{0, top, H - B, T, false};
    d.y_axis(sy, L, W - R, "time per received character [us]", 6);
    const char* groups[] = {"RS-232 interrupt", "DP-RAM (1 byte)", "sum"};
    const double sim[] = {isr, dp, isr + dp}, paper[] = {pisr, pdp, pisr + pdp};
    const double gw = (W - R - L) / 3, bw = 54;
    for (int g = 0; g < 3; ++g) {
        const double cx = L + gw * (g + 0.5);
        for (int k = 0; k < 2; ++k) {
            const double v = k == 0 ? sim[g] : paper[g];
            const double x = cx + (k == 0 ? -bw - 3 : 3), y = sy(v);
            d.rect(x, y, bw, sy.p0 - y, k == 0 ? "#1f77b4" : "#a8a8a8");
            d.text(x + bw / 2, y - 5, num(v, 1), "middle", 12, "font-weight=\"bold\"");
        }
        d.text(cx, H - B + 18, groups[g], "middle", 13);
    }
    // Budget line and margin arrow (on the simulated "sum" bar).
    const double yb = sy(budget);
    d.line(L, yb, W - R, yb, "#c82333", 2, "stroke-dasharray=\"8 4\"");
    const double xs = W - R - 10, ys = sy(isr + dp); // the margin arrow, right of the "sum" bars
    d.line(L + gw * 2.5 - 3, ys, xs, ys, "#555", 1, "stroke-dasharray=\"2 2\"");
    // Labels right of the plot: budget on its line, margin halfway, never on top of each other.
    const double mid = (yb + ys) / 2;
    const double yl_budget = margin >= 0 ? yb - 5 : yb + 15;
    const double yl_margin = margin >= 0 ? std::max(mid + 4, yb + 19) : std::min(mid + 4, yb - 9);
    d.text(W - R + 6, yl_budget, "budget " + num(budget, 1) + " us", "start", 12,
           "fill=\"#c82333\" font-weight=\"bold\"");
    d.line(xs, yb, xs, ys, margin >= 0 ? "#1e7e34" : "#c82333", 1.5);
    d.line(xs - 4, ys, xs + 4, ys, margin >= 0 ? "#1e7e34" : "#c82333", 1.5);
    d.text(W - R + 6, yl_margin, "margin " + num(margin, 1) + " us", "start", 12,
           std::string("fill=\"") + (margin >= 0 ? "#1e7e34" : "#c82333") + "\" font-weight=\"bold\"");
    d.line(xs, mid, W - R + 2, yl_margin - 4, margin >= 0 ? "#1e7e34" : "#c82333", 1);
    // Legend.
    const double ly = H - B + 34;
    d.rect(L, ly, 14, 14, "#1f77b4");
    d.text(L + 20, ly + 12, "simulated (this run)");
    d.rect(L + 180, ly, 14, 14, "#a8a8a8");
    d.text(L + 200, ly + 12, "paper, Table 3 (HP 8086 emulator)");
    d.text(L, H - 14,
           "sum = RS-232 interrupt + DP-RAM byte: the processing each received character costs; margin = budget - sum",
           "start", 11, "fill=\"#555\"");
    return d.str();
}

/// Per-port character latency (stop bit to RXD read): min..max bar, mean and p99 ticks, limit.
std::string char_latency_svg(const json& ports, double limit) {
    const std::size_t n = ports.size();
    const double W = 760, L = 80, R = 210, T = 24, row = 34, B = 54;
    const double H = T + row * static_cast<double>(n) + B;
    svg::Doc d(W, H, "character latency per port");
    double top = limit > 0 ? limit : 1;
    for (const auto& p : ports) top = std::max(top, jd(jo(p, "char_latency_us"), "max"));
    svg::Scale sx{0, top * 1.08, L, W - R, false};
    for (std::size_t i = 0; i < n; ++i) {
        const json& c = jo(ports[i], "char_latency_us");
        const double y = T + row * static_cast<double>(i) + row / 2;
        d.text(L - 8, y + 4, "port " + std::to_string(i), "end", 12);
        if (ju(c, "count") == 0) {
            d.text(L + 6, y + 4, "no characters received", "start", 11, "fill=\"#888\"");
            continue;
        }
        const double mn = jd(c, "min"), mx = jd(c, "max");
        d.rect(sx(mn), y - 8, std::max(sx(mx) - sx(mn), 1.0), 16, colour_of(static_cast<unsigned>(i)),
               "fill-opacity=\"0.35\"");
        d.line(sx(jd(c, "mean")), y - 11, sx(jd(c, "mean")), y + 11, "#0b4f9c", 2.5);
        d.line(sx(jd(c, "p99")), y - 11, sx(jd(c, "p99")), y + 11, "#d46b00", 2.5);
        d.line(sx(mx), y - 11, sx(mx), y + 11, "#c82333", 2.5);
        d.text(W - R + 8, y + 4,
               "mean " + num(jd(c, "mean"), 0) + " / p99 " + num(jd(c, "p99"), 0) + " / max " + num(mx, 0) + " us",
               "start",
               11);
    }
    const double yb = T + row * static_cast<double>(n);
    if (limit > 0) {
        d.line(sx(limit), T - 6, sx(limit), yb, "#c82333", 1.5, "stroke-dasharray=\"6 3\"");
        d.text(sx(limit) - 4, T - 8, "limit " + num(limit, 0) + " us", "end", 11, "fill=\"#c82333\"");
    }
    d.x_axis(sx, yb, "stop bit to RXD read [us]  (bar: min..max; ticks: mean blue, p99 orange, max red)", 8);
    return d.str();
}

/// The logic-analyser picture of [t0, t1]: one row per IR level, a thin bar from IR rise to the
/// first ISR instruction (waiting), a thick bar from there to IRET done (in service), ticks at
/// the INTA cycles and at the EOI. The x axis is (t - origin_us) / unit_us. `rows` are those that
/// reach into [t0, t1], in entry order; `levels` IR rows are drawn.
std::string timeline_svg(const std::vector<TimelineRow>& rows, unsigned levels, double t0, double t1,
                         double origin_us, double unit_us, const std::string& xlabel, const InterruptRow* mark,
                         const std::string& aria) {
    const double W = 1160, L = 118, R = 14, row = 46, B = 52;
    const double T = 62 + (mark ? 58 : 0); // room above the rows for the marked interrupt's labels
    const double H = T + row * levels + B;
    svg::Doc d(W, H, aria);
    svg::Scale sx{(t0 - origin_us) / unit_us, (t1 - origin_us) / unit_us, L, W - R, false};
    auto X = [&](double t_us) { return sx((std::clamp(t_us, t0, t1) - origin_us) / unit_us); };
    // Legend (two lines).
    {
        double x = L, y = 16;
        d.rect(x, y - 3, 26, 6, "#1f77b4", "fill-opacity=\"0.35\"");
        d.text(x + 32, y + 4, "waiting: IR rise .. first ISR instruction", "start", 11);
        x += 270;
        d.rect(x, y - 8, 26, 16, "#1f77b4");
        d.text(x + 32, y + 4, "in service: first ISR instruction .. IRET done", "start", 11);
        x += 300;
        d.rect(x, y - 8, 26, 16, "#1f77b4", "fill-opacity=\"0.4\"");
        d.text(x + 32, y + 4, "RS-232 interrupt without an RX character (TX, timer)", "start", 11);
        x = L;
        y = 38;
        d.line(x + 13, y - 8, x + 13, y + 8, "#000", 1.2);
        d.text(x + 32, y + 4, "INTA 1 / INTA 2", "start", 11);
        x += 150;
        d.line(x + 13, y - 12, x + 13, y + 12, "#d00000", 2);
        d.text(x + 32, y + 4, "EOI (OCW2 write)", "start", 11);
        x += 150;
        d.rect(x, y - 8, 26, 16, "#1f77b4", "stroke=\"#000\" stroke-width=\"1.5\"");
        d.text(x + 32, y + 4, "nested (entered inside another handler)", "start", 11);
    }
    for (unsigned lv = 0; lv < levels; ++lv) {
        const double y0 = T + row * lv, mid = y0 + row / 2;
        if (lv % 2 == 0) d.rect(L, y0, W - R - L, row, "#f6f6f6");
        d.text(L - 8, mid - 2, "IR" + std::to_string(lv), "end", 13, "font-weight=\"bold\"");
        d.text(L - 8, mid + 12, source_name(lv), "end", 11, "fill=\"#555\"");
    }
    const double min_w = 1.0;
    for (const TimelineRow& tr : rows) {
        const InterruptRow& r = tr.row;
        const bool nested = tr.nested;
        if (r.iret_done_us < t0 || r.start_us() > t1) continue;
        const double mid = T + row * r.level + row / 2;
        const std::string c = colour_of(r.level);
        const double xs = X(r.start_us()), xi = X(r.first_isr_us), xe = X(r.iret_done_us);
        if (r.has_rise) d.rect(xs, mid - 3, std::max(xi - xs, 0.0), 6, c, "fill-opacity=\"0.35\"");
        const bool strong = r.level >= 3 || r.rx;
        std::string extra = strong ? "" : " fill-opacity=\"0.4\"";
        if (nested) extra += " stroke=\"#000\" stroke-width=\"1.5\"";
        std::string tip = "IR" + std::to_string(r.level) + " " + r.source + ", vector 0x" + hex(r.vector, 2) +
                          (r.rx ? ", RX" : "") + (nested ? ", nested" : "") + ", probe depth " + std::to_string(r.depth) +
                          "\nIR rise " + (r.has_rise ? num(r.ir_rise_us, 3) + " us" : "-") + "\nINTA1 " +
                          num(r.inta1_us, 3) + " us, INTA2 " + num(r.inta2_us, 3) + " us\nfirst ISR " +
                          num(r.first_isr_us, 3) + " us\nEOI " + (r.has_eoi ? num(r.eoi_us, 3) + " us" : "-") +
                          "\nIRET done " + num(r.iret_done_us, 3) + " us\nlatency " +
                          (r.has_rise ? num(r.latency_us(), 3) : std::string("-")) + " us, service " +
                          num(r.service_us(), 3) + " us";
        d.with_title("<rect x=\"" + num(xi) + "\" y=\"" + num(mid - 10) + "\" width=\"" +
                         num(std::max(xe - xi, min_w)) + "\" height=\"20\" fill=\"" + c + "\"" + extra,
                     tip);
        for (double t : {r.inta1_us, r.inta2_us})
            if (t >= t0 && t <= t1) d.line(X(t), mid - 8, X(t), mid + 8, "#000", 1.2);
        if (r.has_eoi && r.eoi_us >= t0 && r.eoi_us <= t1) d.line(X(r.eoi_us), mid - 13, X(r.eoi_us), mid + 13, "#d00000", 2);
    }
    if (mark) {
        // Name the events of the marked interrupt, logic-analyser style: labels in lanes above the
        // rows (the lowest lane where a label fits), each with a leader line down to its event.
        const double bar_top = T + row * mark->level + row / 2 - 10;
        struct Ev { std::string name; double t; bool on; };
        const Ev evs[] = {{"IR rise", mark->ir_rise_us, mark->has_rise},
                          {"INTA 1", mark->inta1_us, true},
                          {"INTA 2", mark->inta2_us, true},
                          {"first ISR", mark->first_isr_us, true},
                          {"EOI", mark->eoi_us, mark->has_eoi},
                          {"IRET done", mark->iret_done_us, true}};
        std::vector<double> lane_end(5, -1e9);
        for (const Ev& e : evs) {
            if (!e.on) continue;
            std::string text = e.name;
            if (e.t < t0) text = "<- " + e.name + " " + num(t0 - e.t, 1) + " us earlier";
            if (e.t > t1) text = e.name + " " + num(e.t - t1, 1) + " us later ->";
            const double x = X(e.t), w = 6.2 * static_cast<double>(text.size()) + 8;
            const std::string anchor = e.t < t0 ? "start" : e.t > t1 ? "end" : "middle";
            const double a = anchor == "start" ? x : anchor == "end" ? x - w : x - w / 2;
            std::size_t lane = 0;
            while (lane + 1 < lane_end.size() && lane_end[lane] > a) ++lane;
            lane_end[lane] = a + w;
            const double ty = T - 8 - 11.0 * static_cast<double>(lane);
            d.line(x, ty + 2, x, bar_top, "#555", 0.8, "stroke-dasharray=\"2 2\"");
            d.text(x, ty, text, anchor, 10, "fill=\"#000\"");
        }
        if (mark->has_rise)
            d.text(L + 4, bar_top + 34, "latency " + num(mark->latency_us(), 1) + " us, service " +
                                            num(mark->service_us(), 1) + " us",
                   "start", 11, "fill=\"#c82333\" font-weight=\"bold\"");
    }
    d.x_axis(sx, T + row * levels, xlabel, 10);
    return d.str();
}

// ---------------------------------------------------------------------------------------------
// sections

std::string check_relation(const std::string& name) {
    if (name == "frames_delivered" || name.rfind("min_", 0) == 0 || name.rfind("table3_", 0) == 0) return "&ge;";
    return "&le;";
}

void section_checks(std::ostream& o, const json& r) {
    o << "<section id=\"checks\"><h2>Checks</h2>\n<table><tr><th class=\"l\">check</th><th>value</th><th></th>"
         "<th>limit</th><th>result</th></tr>\n";
    for (const auto& c : jo(r, "checks")) {
        const bool ok = c.value("passed", false);
        const std::string name = js(c, "name");
        o << "<tr class=\"" << (ok ? "pass" : "fail") << "\"><td class=\"l\">" << esc(name) << "</td><td class=\"v\">"
          << smart(jd(c, "value")) << "</td><td>" << check_relation(name) << "</td><td>" << smart(jd(c, "limit"))
          << "</td><td class=\"" << (ok ? "ok" : "ko") << "\">"
          << (ok ? "PASS" : c.value("status", "") == "not measured" ? "FAIL (not measured)" : "FAIL") << "</td></tr>\n";
    }
    o << "</table></section>\n";
}

void section_table3(std::ostream& o, const json& r) {
    const json& t = jo(r, "table3");
    const double isr = jd(t, "rs232_isr_us"), dp = jd(t, "dpram_byte_us");
    const double pisr = jd(t, "paper_rs232_isr_us", 82), pdp = jd(t, "paper_dpram_byte_us", 52.553);
    const double margin = jd(t, "margin_us"), budget = jd(t, "budget_us");
    o << "<section id=\"table3\"><h2>Table 3: processing time per character</h2>\n"
      << "<table><tr><th class=\"l\"></th><th>simulated [us]</th><th>paper [us]</th><th>simulated / paper</th></tr>\n";
    auto row = [&o](const std::string& name, double a, double b) {
        o << "<tr><td class=\"l\">" << name << "</td><td>" << num(a, 3) << "</td><td>" << num(b, 3) << "</td><td>"
          << (b > 0 ? num(a / b, 3) : std::string("-")) << "</td></tr>\n";
    };
    row("RS-232 interrupt (mean service of the RX interrupts)", isr, pisr);
    row("DP-RAM (1 byte)", dp, pdp);
    row("sum", isr + dp, pisr + pdp);
    o << "<tr><td class=\"l\">budget (one character time / 3 ports)</td><td>" << num(budget, 3) << "</td><td>"
      << num(budget, 3) << "</td><td></td></tr>\n"
      << "<tr><td class=\"l\">margin = budget - sum</td><td class=\"" << (margin >= 0 ? "ok" : "ko") << "\">"
      << num(margin, 3) << "</td><td>" << num(budget - pisr - pdp, 3) << "</td><td></td></tr>\n"
      << "<tr><td class=\"l\">longest RS-232 RX interrupt</td><td>" << num(jd(t, "rs232_isr_max_us"), 3)
      << "</td><td></td><td></td></tr>\n"
      << "<tr><td class=\"l\">DP-RAM bytes measured</td><td>" << ju(t, "dpram_bytes_measured")
      << "</td><td></td><td></td></tr>\n</table>\n<div class=\"chart\">" << table3_svg(t) << "</div></section>\n";
}

void section_interrupts(std::ostream& o, const json& r, const InterruptLog& log) {
    o << "<section id=\"interrupts\"><h2>Interrupt latency and service time</h2>\n"
      << "<p class=\"note\">Latency = first ISR instruction &minus; IR rise; service = IRET done &minus; first ISR "
         "instruction. <b>rs232_rx</b> are the RS-232 interrupts that took at least one character out of an RX "
         "FIFO (the paper's &ldquo;RS-232 interrupt&rdquo;). Every interrupt is in <code>interrupts.csv</code>.</p>\n"
      << "<table><tr><th class=\"l\">source</th><th>count</th><th>latency min</th><th>mean</th><th>p99</th>"
         "<th>max [us]</th><th>service min</th><th>mean</th><th>p99</th><th>max [us]</th></tr>\n";
    const json& in = jo(r, "interrupts");
    const char* names[] = {"rs232_0", "rs232_1", "rs232_2", "dpram", "rs232_rx"};
    for (const char* n : names) {
        const json& i = jo(in, n);
        const json &l = jo(i, "latency_us"), &s = jo(i, "service_us");
        o << "<tr><td class=\"l\">" << n << "</td><td>" << ju(i, "count") << "</td><td>" << num(jd(l, "min"), 1)
          << "</td><td>" << num(jd(l, "mean"), 1) << "</td><td>" << num(jd(l, "p99"), 1) << "</td><td>"
          << num(jd(l, "max"), 1) << "</td><td>" << num(jd(s, "min"), 1) << "</td><td>" << num(jd(s, "mean"), 1)
          << "</td><td>" << num(jd(s, "p99"), 1) << "</td><td>" << num(jd(s, "max"), 1) << "</td></tr>\n";
    }
    o << "</table>\n";
    for (unsigned k = 0; k < InterruptLog::kHistograms; ++k) {
        const bool rx = k == 4;
        const Samples &lat = log.latency(k), &svc = log.service(k);
        const std::string label = rx ? "rs232_rx (RS-232 interrupts that read a character)"
                                      : "IR" + std::to_string(k) + " " + source_name(k);
        const std::string colour = colour_of(rx ? 0u : k);
        o << "<h3>" << esc(label) << "</h3>\n<div class=\"grid\">"
          << histogram_svg(names[k] + std::string(": latency"), lat, "latency: IR rise to first ISR instruction [us]",
                           colour)
          << histogram_svg(names[k] + std::string(": service time"), svc,
                           "service: first ISR instruction to IRET done [us]", colour)
          << "</div>\n";
    }
    o << "</section>\n";
}

void section_timeline(std::ostream& o, const TimelineWindows& tl) {
    o << "<section id=\"timeline\"><h2>Timeline</h2>\n";
    if (tl.rows() == 0) {
        o << "<p>No interrupt completed in this run.</p></section>\n";
        return;
    }
    const TimeWindow& w = tl.busiest();
    o << "<h3>Busiest " << num(tl.window_us() / 1000, 0) << " ms: " << num(w.start_us / 1000, 3) << " .. "
      << num(w.end_us / 1000, 3) << " ms (" << w.interrupts << " interrupts start in it)</h3>\n"
      << "<p class=\"note\">The window of the run in which the most interrupts start (the earliest such window on "
         "a tie). Hover over a bar for its times.</p>\n<div class=\"chart\">"
      << timeline_svg(tl.busiest_rows(), tl.levels(), w.start_us, w.end_us, 0, 1000, "simulation time [ms]", nullptr,
                      "busiest window")
      << "</div>\n";
    const InterruptRow& worst = tl.worst();
    const double z0 = tl.zoom_start_us(), zoom = tl.zoom_width_us();
    o << "<h3>Zoom on the longest latency: IR" << worst.level << " " << esc(worst.source) << " entered at "
      << num(worst.inta1_us / 1000, 3) << " ms, latency "
      << (worst.has_rise ? num(worst.latency_us(), 1) : std::string("-")) << " us, service "
      << num(worst.service_us(), 1) << " us</h3>\n<div class=\"chart\">"
      << timeline_svg(tl.zoom_rows(), tl.levels(), z0, z0 + zoom, z0, 1, "time after " + num(z0 / 1000, 3) + " ms [us]",
                      &worst, "zoom on the longest latency")
      << "</div></section>\n";
}

/// Both directions for every port kind, as the exactly-once checks count them: what the line
/// observer saw acknowledged on the wire against what the main CPU took from or handed to DP-RAM.
void exactly_once_table(std::ostream& o, const json& ports) {
    o << "<h3>Frames both ways (line observer against the main CPU, every host kind)</h3>\n<table><tr>"
         "<th>port</th><th class=\"l\">host</th><th>commands EOT'd</th><th>main CPU got</th><th>lost</th>"
         "<th>dup</th><th>reordered</th><th>unexpected</th><th>responses handed</th><th>host got</th>"
         "<th>lost</th><th>dropped</th><th>dup</th><th>reordered</th><th>unexpected</th>"
         "<th>response timeouts</th></tr>\n";
    auto cell = [&o](std::uint64_t v, bool bad_if_nonzero) {
        o << "<td" << (bad_if_nonzero && v ? " class=\"bad\"" : "") << ">" << v << "</td>";
    };
    for (std::size_t p = 0; p < ports.size(); ++p) {
        const json& cmd = jo(ports[p], "commands");
        const json& rsp = jo(ports[p], "responses");
        const json& dropped = jo(rsp, "dropped");
        o << "<tr><td>" << p << "</td><td class=\"l\">" << esc(js(ports[p], "host")) << "</td>";
        cell(ju(cmd, "host_eot"), false);
        cell(ju(cmd, "main_cpu_received"), false);
        for (const char* k : {"lost", "duplicates", "reordered", "unexpected"}) cell(ju(cmd, k), true);
        cell(ju(rsp, "main_cpu_handed"), false);
        cell(ju(rsp, "host_received"), false);
        cell(ju(rsp, "lost"), true);
        cell(ju(dropped, "gave_up") + ju(dropped, "port_reset"), true);
        for (const char* k : {"duplicates", "reordered", "unexpected"}) cell(ju(rsp, k), true);
        cell(ju(ports[p], "response_timeouts"), false);
        o << "</tr>\n";
    }
    o << "</table>\n";
}

void section_ports(std::ostream& o, const json& r) {
    const json& ports = jo(r, "ports");
    o << "<section id=\"ports\"><h2>Ports</h2>\n<table><tr><th>port</th><th class=\"l\">host</th>"
         "<th>frames sent</th><th>delivered</th><th>failed</th><th>NAKs</th><th>retries</th><th>timeouts</th>"
         "<th>overruns</th><th>parity err</th><th>framing err</th><th>breaks</th><th>RX FIFO high water</th>"
         "<th>chars rx</th><th>chars tx</th><th>char latency mean</th><th>p99</th><th>max [us]</th></tr>\n";
    auto cell = [&o](std::uint64_t v, bool bad_if_nonzero) {
        o << "<td" << (bad_if_nonzero && v ? " class=\"bad\"" : "") << ">" << v << "</td>";
    };
    for (std::size_t p = 0; p < ports.size(); ++p) {
        const json& j = ports[p];
        const json& c = jo(j, "char_latency_us");
        o << "<tr><td>" << p << "</td><td class=\"l\">" << esc(js(j, "host")) << "</td>";
        cell(ju(j, "frames_sent"), false);
        cell(ju(j, "frames_delivered"), false);
        cell(ju(j, "frames_failed"), true);
        cell(ju(j, "naks"), false);
        cell(ju(j, "retries"), false);
        cell(ju(j, "timeouts"), false);
        cell(ju(j, "overruns"), true);
        cell(ju(j, "parity_errors"), false);
        cell(ju(j, "framing_errors"), false);
        cell(ju(j, "break_detects"), false);
        o << "<td" << (ju(j, "rx_fifo_high_water") >= 4 ? " class=\"bad\"" : "") << ">"
          << ju(j, "rx_fifo_high_water") << " / 4</td>";
        cell(ju(j, "chars_received"), false);
        cell(ju(j, "chars_sent"), false);
        o << "<td>" << num(jd(c, "mean"), 1) << "</td><td>" << num(jd(c, "p99"), 1) << "</td><td>"
          << num(jd(c, "max"), 1) << "</td></tr>\n";
    }
    o << "</table>\n";
    exactly_once_table(o, ports);
    double limit = -1;
    for (const auto& c : jo(r, "checks"))
        if (js(c, "name") == "char_latency_max_us") limit = jd(c, "limit");
    o << "<h3>Character latency (stop bit to RXD read)</h3>\n<div class=\"chart\">" << char_latency_svg(ports, limit)
      << "</div></section>\n";
}

void section_main_cpu(std::ostream& o, const json& r) {
    const json& m = jo(r, "main_cpu");
    o << "<section id=\"main-cpu\"><h2>Main CPU</h2>\n";
    auto summary_row = [&o](const std::string& name, const json& s) {
        o << "<tr><td class=\"l\">" << name << "</td><td>" << ju(s, "count") << "</td><td>" << num(jd(s, "min"), 2)
          << "</td><td>" << num(jd(s, "mean"), 2) << "</td><td>" << num(jd(s, "p50"), 2) << "</td><td>"
          << num(jd(s, "p99"), 2) << "</td><td>" << num(jd(s, "max"), 2) << "</td></tr>\n";
    };
    o << "<table><tr><th class=\"l\"></th><th>count</th><th>min</th><th>mean</th><th>p50</th><th>p99</th>"
         "<th>max [us]</th></tr>\n";
    summary_row("control-cycle jitter (start &minus; ideal start)", jo(m, "cycle_jitter_us"));
    summary_row("IRQ latency (INT from the DP-RAM mailbox)", jo(m, "irq_latency_us"));
    o << "</table>\n<table>";
    const char* counters[] = {"control_cycles", "cycle_overruns", "mailbox_words", "mailbox_overwrites",
                              "unknown_words", "dpram_accesses"};
    for (const char* k : counters)
        o << "<tr><td class=\"l\">" << k << "</td><td>" << ju(m, k) << "</td></tr>\n";
    o << "<tr><td class=\"l\">busy_wait_us</td><td>" << num(jd(m, "busy_wait_us"), 1) << "</td></tr>\n"
      << "<tr><td class=\"l\">cpu_busy_us</td><td>" << num(jd(m, "cpu_busy_us"), 1) << "</td></tr>\n"
      << "<tr><td class=\"l\">DP-RAM BUSY collisions</td><td>" << ju(jo(r, "dpram"), "collisions")
      << "</td></tr>\n</table></section>\n";
}

/// An SVG file's text from its <svg element on (no XML prolog inside the page).
std::string inline_svg(std::string s) {
    const auto at = s.find("<svg");
    if (at != std::string::npos) s.erase(0, at);
    return s;
}

/// The motion section: the figures of a run with main_cpu.motion (control cycle, command
/// latency, CSP path) when there are any, then the trajectory pictures.
void section_motion(std::ostream& o, const json& r, const HtmlOptions& opt) {
    const json& m = jo(r, "motion");
    o << "<section id=\"motion\"><h2>Motion trajectory</h2>\n<p class=\"note\">state " << esc(js(m, "state", "?"))
      << ", " << ju(m, "samples") << " samples (<code>trajectory.csv</code>, <code>trajectory.svg</code>"
      << (opt.trajectory_time_svg.empty() ? "" : ", <code>trajectory_time.svg</code>") << ")</p>\n";
    if (m.contains("control_cycle")) {
        const json& c = jo(m, "control_cycle");
        auto row = [&o](const std::string& name, const json& s) {
            o << "<tr><td class=\"l\">" << name << "</td><td>" << ju(s, "count") << "</td><td>" << num(jd(s, "min"), 2)
              << "</td><td>" << num(jd(s, "mean"), 2) << "</td><td>" << num(jd(s, "p50"), 2) << "</td><td>"
              << num(jd(s, "p99"), 2) << "</td><td>" << num(jd(s, "max"), 2) << "</td></tr>\n";
        };
        o << "<table><tr><th class=\"l\"></th><th>count</th><th>min</th><th>mean</th><th>p50</th><th>p99</th>"
             "<th>max [us]</th></tr>\n";
        row("control-cycle duration (its work)", jo(c, "duration_us"));
        row("control-cycle start jitter", jo(c, "start_jitter_us"));
        row("command latency (host ETX &rarr; first pulse)", jo(m, "command_latency_us"));
        o << "</table>\n";
        if (m.contains("csp")) {
            const json& k = jo(m, "csp");
            o << "<p class=\"note\">CSP path (axes 2/3): " << ju(k, "setpoints") << " set-points, "
              << ju(k, "missed_sync") << " missed the drive's SYNC; set-point error max "
              << num(jd(k, "max_setpoint_error_pulses"), 2) << " pulses, actual path from the circle max "
              << num(jd(k, "max_actual_radial_error_pulses"), 2) << " pulses</p>\n";
        }
    }
    if (!opt.trajectory_svg.empty()) o << "<div class=\"chart\">" << inline_svg(opt.trajectory_svg) << "</div>\n";
    if (!opt.trajectory_time_svg.empty())
        o << "<div class=\"chart\">" << inline_svg(opt.trajectory_time_svg) << "</div>\n";
    o << "</section>\n";
}

std::string slurp_if_exists(const std::filesystem::path& f) {
    if (!std::filesystem::exists(f)) return "";
    std::ifstream in(f);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void write_page(const std::filesystem::path& dir, const std::string& page) {
    const auto f = dir / "report.html";
    std::ofstream out(f);
    if (!out) throw ConfigError(f.string(), 0, "cannot write the file");
    out << page;
    out.flush();
    if (!out) throw ConfigError(f.string(), 0, std::string("cannot write the file: ") + std::strerror(errno));
}

} // namespace

// ---------------------------------------------------------------------------------------------
// the page

std::string render_html(const json& r, const InterruptLog& log, const HtmlOptions& opt) {
    std::ostringstream o;
    const std::string name = js(r, "scenario", "?");
    const bool passed = r.value("passed", false);
    o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>rcsim: " << esc(name)
      << (passed ? " PASSED" : " FAILED") << "</title>\n<style>" << kCss << "</style>\n</head>\n<body>\n";
    o << "<header id=\"header\"><div class=\"banner " << (passed ? "pass" : "fail") << "\"><h1>rcsim run: "
      << esc(name) << "</h1><div class=\"verdict\">" << (passed ? "PASSED" : "FAILED") << "</div></div>\n";
    if (r.value("interrupted", false)) // a signal stopped the run: every figure covers only this far
        o << "<p class=\"interrupted\" id=\"interrupted\">INTERRUPTED at " << num(jd(r, "sim_time_s"), 6)
          << " s simulated: the run was stopped by a signal before its end</p>\n";
    const json& cpu = jo(r, "comm_cpu");
    const double wall = jd(r, "wall_time_s"), rtf = jd(r, "rtf");
    std::uint64_t failed = 0;
    for (const auto& c : jo(r, "checks"))
        if (!c.value("passed", false)) ++failed;
    o << "<table class=\"meta\">\n"
      << "<tr><td>scenario</td><td>" << esc(name) << "</td></tr>\n"
      << "<tr><td>seed</td><td>" << (r.contains("seed") ? r["seed"].dump() : "?") << "</td></tr>\n"
      << "<tr><td>ROM</td><td>" << esc(js(r, "rom", "-")) << "</td></tr>\n"
      << "<tr><td>simulated time</td><td>" << num(jd(r, "sim_time_s"), 6) << " s</td></tr>\n"
      << "<tr><td>wall time, real-time factor</td><td>"
      << (wall > 0 ? num(wall, 3) + " s, RTF " + num(rtf, 2) + " (simulated s per wall s)"
                   : std::string("not recorded (--reproducible)"))
      << "</td></tr>\n"
      << "<tr><td>comm CPU</td><td>" << num(jd(cpu, "clock_hz") / 1e6, 3) << " MHz 8086, " << ju(cpu, "cycles")
      << " cycles, " << ju(cpu, "instructions") << " instructions</td></tr>\n"
      << "<tr><td>interrupts recorded</td><td>" << log.rows() << "</td></tr>\n"
      << "<tr><td>checks</td><td>" << (jo(r, "checks").size() - failed) << " of " << jo(r, "checks").size()
      << " hold</td></tr>\n</table>\n";
    o << "<nav><a href=\"#checks\">Checks</a><a href=\"#table3\">Table 3</a><a href=\"#interrupts\">Interrupts</a>"
         "<a href=\"#timeline\">Timeline</a><a href=\"#ports\">Ports</a><a href=\"#main-cpu\">Main CPU</a>"
      << (opt.trajectory_svg.empty() ? "" : "<a href=\"#motion\">Motion</a>")
      << (opt.flame_svg.empty() ? "" : "<a href=\"#profile\">Profile</a>") << "</nav></header>\n";
    section_checks(o, r);
    section_table3(o, r);
    section_interrupts(o, r, log);
    section_timeline(o, log.timeline());
    section_ports(o, r);
    section_main_cpu(o, r);
    if (!opt.trajectory_svg.empty()) section_motion(o, r, opt);
    if (!opt.flame_svg.empty())
        o << "<section id=\"profile\"><h2>Comm CPU profile</h2>\n<p class=\"note\">Clocks of the comm CPU by call "
             "path (--profile): the whole run at the bottom, the contexts above it, each function above its caller; "
             "hover a box for its clocks. The table is <code>profile.txt</code>, the stacks <code>profile.folded</code> "
             "(docs/tools.md \"Profiler\").</p>\n<div class=\"chart\">"
          << opt.flame_svg << "</div></section>\n";
    o << "<footer><p class=\"note\">Files: <code>report.json</code> (every figure of this page), "
         "<code>interrupts.csv</code> (one row per interrupt). Times are measured from bus cycles and pins: IR rise "
         "(8259A input), INTA 1/2 (T1 of the INTA cycles), first ISR instruction (end of the first code fetch at the "
         "handler), EOI (T1 of the OCW2 write), IRET done (first code fetch at the return address). See "
         "docs/scenarios.md.</p></footer>\n</body>\n</html>\n";
    return o.str();
}

std::string render_html(const json& report, const std::vector<InterruptRow>& unsorted, const HtmlOptions& opt) {
    std::vector<InterruptRow> rows = unsorted;
    sort_rows(rows);
    InterruptLog log(opt.window_us, opt.zoom_us);
    for (const InterruptRow& row : rows) log.add(row);
    log.finish();
    return render_html(report, log, opt);
}

void write_report_html(const std::filesystem::path& dir, const json& report, const InterruptLog& log,
                       const std::string& flame_svg) {
    HtmlOptions opt;
    opt.flame_svg = flame_svg;
    if (report.contains("motion")) {
        opt.trajectory_svg = slurp_if_exists(dir / "trajectory.svg");
        opt.trajectory_time_svg = slurp_if_exists(dir / "trajectory_time.svg");
    }
    write_page(dir, render_html(report, log, opt));
}

std::string render_motion_html(const json& r, const HtmlOptions& opt) {
    std::ostringstream o;
    const std::string name = js(r, "scenario", "?");
    const bool passed = r.value("passed", false);
    o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>rcsim: " << esc(name)
      << (passed ? " PASSED" : " FAILED") << "</title>\n<style>" << kCss << "</style>\n</head>\n<body>\n";
    o << "<header id=\"header\"><div class=\"banner " << (passed ? "pass" : "fail") << "\"><h1>rcsim motion run: "
      << esc(name) << "</h1><div class=\"verdict\">" << (passed ? "PASSED" : "FAILED") << "</div></div>\n"
      << "<table class=\"meta\">\n<tr><td>scenario</td><td>" << esc(name) << "</td></tr>\n"
      << "<tr><td>simulated time</td><td>" << num(jd(r, "sim_time_s"), 6) << " s</td></tr>\n</table>\n"
      << "<nav><a href=\"#checks\">Checks</a><a href=\"#motion\">Motion</a></nav></header>\n";
    section_checks(o, r);
    section_motion(o, r, opt);
    o << "<footer><p class=\"note\">Files: <code>report.json</code>, <code>trajectory.csv</code>. See "
         "docs/motion.md.</p></footer>\n</body>\n</html>\n";
    return o.str();
}

void write_motion_report_html(const std::filesystem::path& dir, const json& report) {
    HtmlOptions opt;
    opt.trajectory_svg = slurp_if_exists(dir / "trajectory.svg");
    opt.trajectory_time_svg = slurp_if_exists(dir / "trajectory_time.svg");
    write_page(dir, render_motion_html(report, opt));
}

} // namespace rcsim::report
