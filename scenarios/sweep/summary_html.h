// rcsim — the pictures of summary.html and compare.html, drawn with the one chart module
// (scenarios/report/svg.h): figures against a sweep axis, and overlaid histograms.
#pragma once

#include <string>
#include <vector>

namespace rcsim::sweep::html {

/// The style sheet both pages embed (each page is one self-contained file).
extern const char* const kCss;

struct XyPoint {
    double x = 0, y = 0;
    bool failed = false;  // drawn as a red cross
    std::string tip;      // hover text
    bool stopped = false; // interrupted before its end: drawn as a dashed grey ring, not a cross
};

struct XySeries {
    std::string label;
    std::vector<XyPoint> points; // sorted by x
};

/// `y` against `x`, one line per series; a log x axis when x spans a factor of 20 or more.
std::string xy_chart(const std::string& title, const std::string& xlabel, const std::string& ylabel,
                     const std::vector<XySeries>& series);

/// Two histograms of the same quantity over one set of bins, overlaid (baseline and current).
std::string overlaid_histogram(const std::string& title, const std::vector<double>& baseline,
                               const std::vector<double>& current);

/// A number for a table cell: up to 6 significant digits, "-" for null.
std::string cell(double v);

} // namespace rcsim::sweep::html
