// rcsim search's outputs (docs/search.md "What a search writes"): the witness worst.yaml,
// search.json, search.html, and the lines it prints at the end.
#pragma once

#include "scenarios/search/search.h"

#include <filesystem>
#include <ostream>
#include <string>

namespace rcsim::search {

struct PageInput {
    const SearchOptions& options;
    std::string scenario_name;
    std::string algorithm;
    unsigned starts = 0;
    std::filesystem::path dir;
    const SearchResult& result;
};

/// The command that reproduces the witness alone (with the search's --symbols).
std::string reproduce_command(const PageInput& in);

/// What held the witness's figure, from its report: the worst case's cause for an interrupt
/// latency, Table 3's terms for a Table 3 figure, else the first failed check's reason, else the
/// verdict's.
std::string witness_cause(const nlohmann::json& report, const std::string& figure);

/// search.json.
nlohmann::json search_json(const PageInput& in);

/// search.html: the page of one search (self-contained, its charts inline SVG), from the search
/// and its search.json (`summary`: the axes' influence, the witness's cause).
std::string search_html(const PageInput& in, const nlohmann::json& summary);

/// Writes DIR/worst.yaml (when a run measured the figure), DIR/search.json and DIR/search.html;
/// returns what search.json holds.
nlohmann::json write_witness(const PageInput& in);

/// The search's last lines on stdout: best figure and run, the witness, the page.
void print_outcome(const PageInput& in, std::ostream& out);

} // namespace rcsim::search
