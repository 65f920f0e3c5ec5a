// rcsim — the SVG charts of report.html: histograms, Table 3, character latency, the interrupt
// timeline. See html_parts.h.
#include "scenarios/report/html_parts.h"

#include "scenarios/report/svg.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace rcsim::report {

using svg::esc;
using svg::num;
using json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// histograms

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



// ---------------------------------------------------------------------------------------------
// charts

namespace html {


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


} // namespace html
} // namespace rcsim::report
