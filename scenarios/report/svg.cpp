// rcsim — the chart module. See svg.h.
#include "scenarios/report/svg.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace rcsim::svg {

std::string num(double v, int decimals) {
    if (!std::isfinite(v)) return "0";
    // std::to_chars in fixed notation gives the digits of printf("%.*f") (the C standard's
    // correctly rounded conversion, ties to even) without the locale and format parsing that
    // made snprintf a tenth of a report's time (interrupts.csv, report.html).
    char buf[400]; // DBL_MAX in fixed notation is 309 digits, plus 9 decimals
    const auto res = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, std::clamp(decimals, 0, 9));
    std::string s(buf, res.ptr);
    if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
    return s;
}

std::string esc(const std::string& s) {
    std::string o;
    o.reserve(s.size());
    for (char c : s) {
        switch (c) {
        case '&': o += "&amp;"; break;
        case '<': o += "&lt;"; break;
        case '>': o += "&gt;"; break;
        case '"': o += "&quot;"; break;
        case '\'': o += "&#39;"; break;
        default: o += c;
        }
    }
    return o;
}

double nice_step(double span, int target) {
    if (!(span > 0) || target < 1) return 1;
    const double raw = span / target;
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * mag >= raw * 0.999) return m * mag;
    return 10 * mag;
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
    std::vector<double> t;
    const double step = nice_step(hi - lo, target);
    const double first = std::ceil(lo / step - 1e-9);
    for (double k = first; k * step <= hi + step * 1e-9 && t.size() < 1000; k += 1) t.push_back(k * step);
    return t;
}

int decimals_for(double step) {
    if (step >= 1) return 0;
    return std::min(9, static_cast<int>(std::ceil(-std::log10(step) - 1e-9)));
}

NiceRange nice_range(double lo, double hi, int target) {
    if (!(hi > lo)) {
        const double step = nice_step(std::max(std::abs(lo), 1.0), target);
        return {std::floor(lo / step) * step - step, std::floor(lo / step) * step + step, step};
    }
    // The step for the span, then the bounds out to multiples of it; the wider span may need
    // the next step up (at most once more: the bounds grow by less than two steps).
    double step = nice_step(hi - lo, target);
    for (int i = 0; i < 2; ++i) {
        const double a = std::floor(lo / step + 1e-9) * step, b = std::ceil(hi / step - 1e-9) * step;
        if ((b - a) / step <= target + 1 || i == 1) return {a, b, step};
        step = nice_step(b - a, target);
    }
    return {lo, hi, step};
}

ColumnDecimator::ColumnDecimator(double t0, double t1, unsigned columns)
    : t0_(t0), t1_(t1 > t0 ? t1 : t0 + 1), cols_(std::max(columns, 1u)) {}

void ColumnDecimator::add(double t, double v) {
    ++samples_;
    const double f = (t - t0_) / (t1_ - t0_) * static_cast<double>(cols_.size());
    const double last = static_cast<double>(cols_.size() - 1);
    const std::size_t i = !(f > 0) ? 0 : f >= last ? cols_.size() - 1 : static_cast<std::size_t>(f);
    Column& c = cols_[i];
    const Pick p{t, v};
    if (!c.any) {
        c = Column{true, p, p, p, p};
        return;
    }
    if (v < c.low.v) c.low = p;
    if (v > c.high.v) c.high = p;
    c.last = p;
}

std::vector<std::pair<double, double>> ColumnDecimator::points() const {
    std::vector<std::pair<double, double>> out;
    for (const Column& c : cols_) {
        if (!c.any) continue;
        Pick picks[4] = {c.first, c.low, c.high, c.last};
        std::stable_sort(std::begin(picks), std::end(picks), [](const Pick& a, const Pick& b) { return a.t < b.t; });
        for (const Pick& p : picks)
            if (out.empty() || out.back().first != p.t || out.back().second != p.v) out.emplace_back(p.t, p.v);
    }
    return out;
}

PathDecimator::PathDecimator(double width, double height, double min_step, std::size_t max_points, double cell)
    : w_(width), h_(height), min_step_(min_step), cell_(cell), max_points_(max_points),
      cols_(static_cast<std::size_t>(std::ceil(width / cell)) + 1),
      rows_(static_cast<std::size_t>(std::ceil(height / cell)) + 1) {}

void PathDecimator::visit(const Point& p) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return;
    const auto cx = static_cast<std::size_t>(std::clamp(p.x, 0.0, w_) / cell_);
    const auto cy = static_cast<std::size_t>(std::clamp(p.y, 0.0, h_) / cell_);
    visited_[cy * cols_ + cx] = true;
}

void PathDecimator::add(const Point& p) {
    if (cells_mode_) return visit(p);
    if (!points_.empty() && std::abs(p.x - points_.back().x) < min_step_ && std::abs(p.y - points_.back().y) < min_step_)
        return;
    points_.push_back(p);
    if (points_.size() <= max_points_) return;
    // Too long a polyline: from here on, the cells it visited.
    cells_mode_ = true;
    visited_.assign(cols_ * rows_, false);
    for (const Point& q : points_) visit(q);
    points_.clear();
    points_.shrink_to_fit();
}

std::vector<Point> PathDecimator::cells() const {
    std::vector<Point> out;
    for (std::size_t y = 0; y < rows_ && cells_mode_; ++y)
        for (std::size_t x = 0; x < cols_; ++x)
            if (visited_[y * cols_ + x]) out.push_back({(double(x) + 0.5) * cell_, (double(y) + 0.5) * cell_});
    return out;
}

double Scale::operator()(double v) const {
    double a = lo, b = hi;
    if (log) {
        v = std::log10(std::max(v, lo));
        a = std::log10(lo);
        b = std::log10(hi);
    }
    if (b == a) return p0;
    return p0 + (v - a) / (b - a) * (p1 - p0);
}

Doc::Doc(double width, double height, const std::string& aria_label) : w_(width), h_(height), label_(aria_label) {}

void Doc::rect(double x, double y, double w, double h, const std::string& fill, const std::string& extra) {
    body_ << "<rect x=\"" << num(x) << "\" y=\"" << num(y) << "\" width=\"" << num(std::max(w, 0.0))
          << "\" height=\"" << num(std::max(h, 0.0)) << "\" fill=\"" << fill << "\"" << (extra.empty() ? "" : " ")
          << extra << "/>\n";
}

void Doc::line(double x1, double y1, double x2, double y2, const std::string& stroke, double width,
               const std::string& extra) {
    body_ << "<line x1=\"" << num(x1) << "\" y1=\"" << num(y1) << "\" x2=\"" << num(x2) << "\" y2=\"" << num(y2)
          << "\" stroke=\"" << stroke << "\" stroke-width=\"" << num(width) << "\"" << (extra.empty() ? "" : " ")
          << extra << "/>\n";
}

void Doc::text(double x, double y, const std::string& s, const std::string& anchor, double size,
               const std::string& extra) {
    body_ << "<text x=\"" << num(x) << "\" y=\"" << num(y) << "\"";
    if (anchor != "start") body_ << " text-anchor=\"" << anchor << "\"";
    if (size != 12) body_ << " font-size=\"" << num(size) << "\"";
    if (!extra.empty()) body_ << " " << extra;
    body_ << ">" << esc(s) << "</text>\n";
}

void Doc::vtext(double x, double y, const std::string& s, double size) {
    body_ << "<text transform=\"translate(" << num(x) << "," << num(y) << ") rotate(-90)\" text-anchor=\"middle\"";
    if (size != 12) body_ << " font-size=\"" << num(size) << "\"";
    body_ << ">" << esc(s) << "</text>\n";
}

void Doc::with_title(const std::string& element, const std::string& title) {
    body_ << element << "><title>" << esc(title) << "</title></" << element.substr(1, element.find(' ') - 1)
          << ">\n";
}

void Doc::polyline(const std::vector<Point>& points, const std::string& stroke, double width,
                   const std::string& extra) {
    body_ << "<polyline fill=\"none\" stroke=\"" << stroke << "\" stroke-width=\"" << num(width) << "\"";
    if (!extra.empty()) body_ << " " << extra;
    body_ << " points=\"";
    for (std::size_t i = 0; i < points.size(); ++i)
        body_ << (i ? " " : "") << num(points[i].x) << ',' << num(points[i].y);
    body_ << "\"/>\n";
}

void Doc::marker(double x, double y, Marker shape, const std::string& colour, double size) {
    const double h = size / 2;
    switch (shape) {
    case Marker::circle:
        body_ << "<circle cx=\"" << num(x) << "\" cy=\"" << num(y) << "\" r=\"" << num(h) << "\" fill=\"" << colour
              << "\"/>\n";
        break;
    case Marker::square: rect(x - h, y - h, size, size, colour); break;
    case Marker::cross:
        line(x - h, y - h, x + h, y + h, colour, 1.5);
        line(x - h, y + h, x + h, y - h, colour, 1.5);
        break;
    }
}

void Doc::dots(const std::vector<Point>& points, const std::string& fill, double size) {
    if (points.empty()) return;
    body_ << "<path fill=\"" << fill << "\" d=\"";
    const double h = size / 2;
    for (const Point& p : points)
        body_ << 'M' << num(p.x - h) << ' ' << num(p.y - h) << 'h' << num(size) << 'v' << num(size) << 'h' << num(-size)
              << 'z';
    body_ << "\"/>\n";
}

void Doc::arrow(const Point& tip, double dx, double dy, const std::string& fill, double size) {
    const double n = std::hypot(dx, dy);
    if (!(n > 0)) return;
    const double ux = dx / n, uy = dy / n; // along the path
    const double bx = tip.x - ux * size, by = tip.y - uy * size;
    const double px = -uy * size * 0.45, py = ux * size * 0.45; // across it
    body_ << "<polygon fill=\"" << fill << "\" points=\"" << num(tip.x) << ',' << num(tip.y) << ' ' << num(bx + px)
          << ',' << num(by + py) << ' ' << num(bx - px) << ',' << num(by - py) << "\"/>\n";
}

void Doc::title(const std::string& s, double y, double size) { text(w_ / 2, y, s, "middle", size); }

void Doc::frame(double x, double y, double w, double h, const std::string& stroke) {
    rect(x, y, w, h, "none", "stroke=\"" + stroke + "\"");
}

void Doc::legend(double x, double y, const std::vector<LegendEntry>& entries, double row) {
    for (const LegendEntry& e : entries) {
        if (e.box) rect(x + 8, y - 7, 14, 14, e.colour);
        else line(x, y, x + 30, y, e.colour, 2, e.dash.empty() ? "" : "stroke-dasharray=\"" + e.dash + "\"");
        text(x + 36, y + 4, e.label);
        y += row;
    }
}

void Doc::y_axis(const Scale& s, double x0, double x1, const std::string& title, int target_ticks) {
    std::vector<double> ticks;
    int dec = 0;
    if (s.log) {
        for (double v = std::pow(10.0, std::ceil(std::log10(s.lo) - 1e-9)); v <= s.hi * (1 + 1e-9); v *= 10)
            ticks.push_back(v);
    } else {
        ticks = nice_ticks(s.lo, s.hi, target_ticks);
        dec = decimals_for(nice_step(s.hi - s.lo, target_ticks));
    }
    for (double v : ticks) {
        const double y = s(v);
        line(x0, y, x1, y, "#e3e3e3");
        line(x0 - 4, y, x0, y, "#333");
        text(x0 - 7, y + 4, num(v, dec), "end", 11);
    }
    line(x0, std::min(s.p0, s.p1), x0, std::max(s.p0, s.p1), "#333");
    vtext(x0 - 44, (s.p0 + s.p1) / 2, title);
}

void Doc::x_axis(const Scale& s, double y, const std::string& title, int target_ticks, bool integers) {
    // A whole quantity never gets a tick between two of its values: the step is at least 1.
    const double step = integers ? std::max(1.0, nice_step(s.hi - s.lo, target_ticks)) : nice_step(s.hi - s.lo, target_ticks);
    std::vector<double> ticks;
    for (double k = std::ceil(s.lo / step - 1e-9); k * step <= s.hi + step * 1e-9 && ticks.size() < 1000; k += 1)
        ticks.push_back(k * step);
    const int dec = decimals_for(step);
    for (double v : ticks) {
        const double x = s(v);
        line(x, y, x, y + 4, "#333");
        text(x, y + 16, num(v, dec), "middle", 11);
    }
    line(std::min(s.p0, s.p1), y, std::max(s.p0, s.p1), y, "#333");
    text((s.p0 + s.p1) / 2, y + 34, title, "middle");
}

std::string Doc::str() const {
    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(w_, 0) << "\" height=\"" << num(h_, 0)
      << "\" viewBox=\"0 0 " << num(w_, 0) << " " << num(h_, 0)
      << "\" font-family=\"sans-serif\" font-size=\"12\" role=\"img\"";
    if (!label_.empty()) o << " aria-label=\"" << esc(label_) << "\"";
    o << ">\n" << body_.str() << "</svg>\n";
    return o.str();
}

} // namespace rcsim::svg
