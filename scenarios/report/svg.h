// rcsim — the one chart module: a tiny SVG writer for every picture rcsim draws (report.html's
// charts, trajectory.svg). Plain C++, no libraries.
//
// Every number goes through `num` (fixed decimals, C locale, no "-0"), so the same picture is
// always the same bytes. Text is XML-escaped. Axes: linear or log10, with "nice" tick values;
// a chart is a Doc with a title, axes, polylines, markers and a legend.
#pragma once

#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace rcsim::svg {

/// Fixed-point formatting with `decimals` digits; "-0.00" becomes "0.00".
std::string num(double v, int decimals = 1);
/// Escapes &, <, >, " and ' for XML text and attribute values.
std::string esc(const std::string& s);

struct Point {
    double x = 0, y = 0; // pixels
};

/// A step of 1, 2 or 5 x 10^k giving about `target` divisions of `span`.
double nice_step(double span, int target);
/// Tick values k*step inside [lo, hi] (with step = nice_step(hi - lo, target)).
std::vector<double> nice_ticks(double lo, double hi, int target);
/// Decimals needed to print multiples of `step` exactly enough (0 for step >= 1).
int decimals_for(double step);

/// [lo, hi] widened to multiples of a nice step for about `target` divisions: the axis then
/// starts and ends on a tick. An empty span becomes one step around the value.
struct NiceRange {
    double lo = 0, hi = 1, step = 1;
};
NiceRange nice_range(double lo, double hi, int target);

/// Min/max per pixel column, streaming: a series of any length over [t0, t1] becomes at most four
/// points per column (the column's first, lowest, highest and last sample, in time order), so
/// every peak survives and the picture's size is bounded by its width. Samples outside [t0, t1]
/// go to the first or last column.
class ColumnDecimator {
public:
    ColumnDecimator(double t0, double t1, unsigned columns);
    void add(double t, double v);
    /// The kept samples (t, v) in time order.
    std::vector<std::pair<double, double>> points() const;
    std::size_t samples() const { return samples_; }

private:
    struct Pick {
        double t = 0, v = 0;
    };
    struct Column {
        bool any = false;
        Pick first, low, high, last;
    };
    double t0_, t1_;
    std::vector<Column> cols_;
    std::size_t samples_ = 0;
};

/// An X-Y path in pixels, bounded: consecutive points closer than `min_step` pixels are merged;
/// once more than `max_points` are kept (a path that goes round many times) it becomes the set
/// of `cell`-pixel cells it visited, drawn as dots, so the picture's size stays bounded by its
/// area whatever the length of the run.
class PathDecimator {
public:
    PathDecimator(double width, double height, double min_step = 0.5, std::size_t max_points = 20000, double cell = 2);
    void add(const Point& p);
    bool as_cells() const { return cells_mode_; }
    const std::vector<Point>& points() const { return points_; } // the polyline (not as_cells())
    std::vector<Point> cells() const;                             // cell centres (as_cells())

private:
    double w_, h_, min_step_, cell_;
    std::size_t max_points_;
    std::vector<Point> points_;
    bool cells_mode_ = false;
    std::size_t cols_, rows_;
    std::vector<bool> visited_;
    void visit(const Point& p);
};

/// A value axis mapped onto pixels [p0, p1] (p1 < p0 for a y axis growing upwards).
struct Scale {
    double lo = 0, hi = 1, p0 = 0, p1 = 1;
    bool log = false; // log10; lo must then be > 0
    double operator()(double v) const;
};


enum class Marker { circle, square, cross };

/// One row of a legend: a line sample (solid, or dashed with `dash` = "4 3") or a filled box.
struct LegendEntry {
    std::string label, colour;
    std::string dash = "";
    bool box = false;
};

/// An SVG document built element by element.
class Doc {
public:
    Doc(double width, double height, const std::string& aria_label = "");

    void rect(double x, double y, double w, double h, const std::string& fill, const std::string& extra = "");
    void line(double x1, double y1, double x2, double y2, const std::string& stroke, double width = 1,
              const std::string& extra = "");
    /// anchor: start | middle | end.
    void text(double x, double y, const std::string& s, const std::string& anchor = "start", double size = 12,
              const std::string& extra = "");
    /// Vertical text (rotated -90 degrees), centred on (x, y): y-axis titles.
    void vtext(double x, double y, const std::string& s, double size = 12);
    /// An element with a hover tooltip (<title>), e.g. a bar: `element` without its closing "/>".
    void with_title(const std::string& element, const std::string& title);
    /// An open line through `points`, numbers with one decimal (a tenth of a pixel).
    void polyline(const std::vector<Point>& points, const std::string& stroke, double width = 1.5,
                  const std::string& extra = "");
    /// A marker of `size` pixels centred on (x, y); a cross is drawn with `colour` as its stroke.
    void marker(double x, double y, Marker shape, const std::string& colour, double size = 6);
    /// The chart's title: centred across the document, baseline at y.
    void title(const std::string& s, double y = 30, double size = 16);
    /// The outline of a plot area.
    void frame(double x, double y, double w, double h, const std::string& stroke = "#333");
    /// A legend whose first row's sample starts at (x, y), one row every `row` pixels downwards.
    void legend(double x, double y, const std::vector<LegendEntry>& entries, double row = 18);
    /// Small dots (1.5 px squares) at `points`, as one path element.
    void dots(const std::vector<Point>& points, const std::string& fill, double size = 1.5);
    /// A filled triangle at `tip` pointing along (dx, dy): a direction mark on a path.
    void arrow(const Point& tip, double dx, double dy, const std::string& fill, double size = 10);
    /// Raw SVG markup.
    void raw(const std::string& s) { body_ << s; }

    /// Left axis with ticks, grid lines across [x0, x1] and a rotated title.
    void y_axis(const Scale& s, double x0, double x1, const std::string& title, int target_ticks = 5);
    /// Bottom axis at pixel y with ticks and a title below. `integers`: a quantity that is
    /// whole (wait states, a count), ticked at whole values only.
    void x_axis(const Scale& s, double y, const std::string& title, int target_ticks = 8, bool integers = false);

    std::string str() const;

private:
    double w_, h_;
    std::string label_;
    std::ostringstream body_;
};

} // namespace rcsim::svg
