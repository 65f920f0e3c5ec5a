#include "scenarios/config/search_section.h"

#include "models/plumbing/config_error.h"
#include "scenarios/config/yaml_map.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace rcsim {

namespace {

/// A number as written: its value, and whether it is a whole number written without a point or
/// an exponent. False when the text is not a finite number.
bool read_number(const std::string& text, double& value, bool& whole) {
    if (text.empty()) return false;
    char* end = nullptr;
    value = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || !std::isfinite(value)) return false;
    whole = text.find_first_of(".eE") == std::string::npos;
    return true;
}

/// LO and HI checked: numbers, LO <= HI. `fail` gets the reason.
template <typename Fail>
void check_range(SearchAxisRange& r, const std::string& lo, const std::string& hi, const Fail& fail) {
    if (r.path.empty()) fail("an axis needs a key path");
    bool lo_whole = false, hi_whole = false;
    if (!read_number(lo, r.lo, lo_whole)) fail("axis '" + r.path + "': '" + lo + "' is not a number");
    if (!read_number(hi, r.hi, hi_whole)) fail("axis '" + r.path + "': '" + hi + "' is not a number");
    if (r.lo > r.hi) fail("axis '" + r.path + "': the low end " + lo + " is above the high end " + hi);
    r.whole = lo_whole && hi_whole;
}

} // namespace

const std::vector<std::string>& search_algorithms() {
    static const std::vector<std::string> names{"subplex", "neldermead", "cobyla", "direct-l", "crs2"};
    return names;
}

SearchAxisRange parse_axis_text(const std::string& text) {
    SearchAxisRange r;
    const std::size_t eq = text.find('='), dots = text.find("..", eq == std::string::npos ? 0 : eq);
    if (eq == std::string::npos || dots == std::string::npos)
        throw ConfigError("--axis '" + text + "' must be PATH=LO..HI (e.g. ports[0].start_ms=50..51.2)");
    r.path = text.substr(0, eq);
    check_range(r, text.substr(eq + 1, dots - eq - 1), text.substr(dots + 2),
                [&text](const std::string& why) -> void { throw ConfigError("--axis '" + text + "': " + why); });
    return r;
}

std::optional<SearchSection> read_search_section(const YAML::Node& root, const std::string& file) {
    if (!root.IsMap() || !root["search"]) return std::nullopt;
    YamlMap m(root["search"], file, "search.");
    SearchSection s;
    s.line = YamlMap::line_of(root["search"]);
    if (m.has("axes")) {
        const YAML::Node axes = m.child("axes");
        if (!axes.IsMap() || axes.size() == 0) m.fail(axes, "'search.axes' must map key paths to [LO, HI]");
        for (const auto& kv : axes) {
            SearchAxisRange r;
            r.line = YamlMap::line_of(kv.first);
            r.path = kv.first.Scalar();
            const YAML::Node v = kv.second;
            auto fail = [&](const std::string& why) -> void { m.fail(kv.first, "'search.axes': " + why); };
            if (!v.IsSequence() || v.size() != 2 || !v[0].IsScalar() || !v[1].IsScalar())
                fail("axis '" + r.path + "' must be [LO, HI]");
            check_range(r, v[0].Scalar(), v[1].Scalar(), fail);
            s.axes.push_back(r);
        }
    }
    if (m.has("algorithm")) {
        std::string names;
        for (const auto& a : search_algorithms()) names += (names.empty() ? "" : ", ") + a;
        s.algorithm = m.get<std::string>("algorithm", "");
        const auto& all = search_algorithms();
        if (std::find(all.begin(), all.end(), s.algorithm) == all.end())
            m.fail(m.child("algorithm"), "'search.algorithm' = '" + s.algorithm + "' is not one of " + names);
    }
    if (m.has("starts")) s.starts = static_cast<unsigned>(m.integer("starts", 1, 1, 64));
    m.finish();
    return s;
}

} // namespace rcsim
