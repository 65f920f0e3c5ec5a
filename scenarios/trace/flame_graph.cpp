#include "scenarios/trace/flame_graph.h"

#include "scenarios/report/svg.h"

#include <algorithm>

namespace rcsim::trace {

namespace {

constexpr double kRow = 17, kTop = 34, kMargin = 10;

// A warm colour from the name (FNV-1a), the same for the same function in every picture.
std::string colour_of(const std::string& name) {
    std::uint32_t h = 2166136261u;
    for (const char c : name) h = (h ^ static_cast<unsigned char>(c)) * 16777619u;
    const unsigned r = 205 + h % 50, g = 80 + (h >> 8) % 130, b = 40 + (h >> 16) % 50;
    return "rgb(" + std::to_string(r) + "," + std::to_string(g) + "," + std::to_string(b) + ")";
}

struct Layout {
    const CycleProfiler& p;
    svg::Doc& doc;
    double scale;    // pixels per clock
    double base_y;   // top of the bottom row
    double us_per_clock;
    std::uint64_t total;

    unsigned depth(unsigned node) const {
        unsigned d = 0;
        for (const auto& [name, c] : p.tree()[node].children) d = std::max(d, depth(c));
        return d + 1;
    }
    void draw(unsigned node, double x, unsigned level, const std::string& path) const {
        const std::uint64_t clocks = p.total_of(node);
        const double w = static_cast<double>(clocks) * scale;
        if (w < 0.5) return;
        const std::string& name = node == 0 ? std::string("all") : p.tree()[node].name;
        const double y = base_y - level * kRow;
        const std::string where = path.empty() ? name : path + " > " + name;
        char tip[160];
        std::snprintf(tip, sizeof tip, ": %llu clocks, %.2f%%, %.2f us", static_cast<unsigned long long>(clocks),
                      total ? 100.0 * static_cast<double>(clocks) / static_cast<double>(total) : 0.0,
                      static_cast<double>(clocks) * us_per_clock);
        doc.with_title("<rect x=\"" + svg::num(x) + "\" y=\"" + svg::num(y) + "\" width=\"" + svg::num(w) +
                           "\" height=\"" + svg::num(kRow - 1) + "\" fill=\"" + colour_of(name) + "\"",
                       where + tip);
        const std::size_t fits = static_cast<std::size_t>(w / 7);
        if (fits >= 3) {
            const std::string label = name.size() <= fits ? name : name.substr(0, fits - 2) + "..";
            doc.text(x + 3, y + kRow - 5, label, "start", 11);
        }
        double cx = x;
        for (const auto& [child_name, c] : p.tree()[node].children) {
            draw(c, cx, level + 1, node == 0 ? "" : where);
            cx += static_cast<double>(p.total_of(c)) * scale;
        }
    }
};

} // namespace

std::string flame_graph_svg(const CycleProfiler& profile, double clock_hz, double width) {
    const std::uint64_t total = profile.total_of(0);
    // Depth first, to size the picture.
    svg::Doc probe_doc(1, 1);
    Layout measure{profile, probe_doc, 0, 0, 0, total};
    const unsigned rows = measure.depth(0);
    const double height = kTop + rows * kRow + kMargin;
    svg::Doc doc(width, height, "flame graph of the comm CPU's clocks");
    doc.title("Comm CPU clocks by call path (" + std::to_string(total) + " clocks)", 20, 14);
    const double us = clock_hz > 0 ? 1e6 / clock_hz : 0;
    Layout l{profile, doc, total ? (width - 2 * kMargin) / static_cast<double>(total) : 0,
             kTop + (rows - 1) * kRow, us, total};
    l.draw(0, kMargin, 0, "");
    return doc.str();
}

} // namespace rcsim::trace
