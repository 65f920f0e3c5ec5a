// rcsim — the `search:` section of a scenario file (docs/search.md): the axes `rcsim search`
// varies instead of its default ones, and the optimiser it uses. A run ignores the section; it is
// read here, with the rest of the file, so that a malformed one is bad input for every command.
#pragma once

#include <yaml-cpp/yaml.h>

#include <optional>
#include <string>
#include <vector>

namespace rcsim {

/// One axis as the file writes it: `PATH: [LO, HI]`.
struct SearchAxisRange {
    std::string path;
    double lo = 0, hi = 0;
    bool whole = false; // LO and HI both written as integers
    int line = 0;
};

struct SearchSection {
    std::vector<SearchAxisRange> axes; // empty: the default axes
    std::string algorithm;             // "" = the command's default
    std::optional<unsigned> starts;    // optimiser streams
    int line = 0;
};

/// The optimisers `rcsim search` offers (NLopt's names in docs/search.md), the first the default.
const std::vector<std::string>& search_algorithms();

/// "PATH=LO..HI" (an `--axis` argument) as a range; throws ConfigError naming the text.
SearchAxisRange parse_axis_text(const std::string& text);

/// The `search:` section of a scenario document, read strictly: errors name `file` and the line.
/// None when the document has no such section.
std::optional<SearchSection> read_search_section(const YAML::Node& root, const std::string& file);

} // namespace rcsim
