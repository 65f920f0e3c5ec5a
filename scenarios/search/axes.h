// rcsim — the axes of a search (docs/search.md "Axes"): what a real installation leaves free, each
// a range of one value, and how a point of the search becomes a scenario.
//
// An axis is a scenario key path (anything a sweep can set, docs/regression.md "Key paths") or one
// of three per-port axes the scenario has no key for:
//   ports[i].char_phase_us      added to the port's start_ms: where in a character time it starts
//   ports[i].frame_phase_chars  added to start_ms in whole characters: where in a frame it starts
//   ports[i].baud               the host's baud rate (its `format` with another rate)
#pragma once

#include "scenarios/config/scenario.h"
#include "scenarios/config/search_section.h"

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

namespace rcsim::search {

struct Axis {
    std::string path;
    double lo = 0, hi = 0;
    bool whole = false;  // an integer axis: seed, sizes, characters, baud
    std::string origin;  // where the range comes from, for search.json and the page

    /// The axis's value at u in [0, 1]: lo + u (hi - lo), or for a whole axis the integer cell
    /// of hi - lo + 1 equal cells that u falls in (every value equally likely under a uniform u).
    double at(double u) const;
    /// The value as it is written into the scenario and the run's parameters (whole numbers
    /// without a point; others with 10 significant digits, so the text is the value).
    std::string text(double value) const;
};

/// The host's baud tolerance the default `ports[i].baud` axis spans, as a fraction each way. With
/// 16x sampling the two ends may drift (0.5 - 1/16) / 10.5 = 4.2 % apart over an 8E1 character;
/// practice keeps their sum within about 2-3 %. The 82510's rate is exact (18.432 MHz / 32 / 60 =
/// 9600), so the host may carry all of it (docs/search.md "Axes").
constexpr double kBaudTolerance = 0.02;
/// The main CPU's command time varies by this fraction each way (a scenario sets one figure).
constexpr double kCommandTimeSpread = 0.5;
/// The seed axis: this many seeds from 1.
constexpr double kSeeds = 1000000;

/// The axes a real installation leaves free in `s` (read from `doc`, its document): per port with
/// generated protocol traffic its start phase in a character and in a frame, its baud, its frame
/// length and (fixed, poisson, burst) its gaps; the main CPU's command time; the seed.
std::vector<Axis> default_axes(const Scenario& s);

/// The axes of a section or of `--axis` arguments, checked against the scenario: the path must be
/// a key the document can hold or a per-port axis of an existing port. Throws ConfigError naming
/// the axis (and the file's line for a section).
std::vector<Axis> written_axes(const std::vector<SearchAxisRange>& ranges, const Scenario& s, const std::string& origin);

/// The scenario document of one point (a value per axis, in axis order): `base` with the search
/// section removed and every axis applied. Throws std::invalid_argument naming the axis.
YAML::Node apply(const YAML::Node& base, const Scenario& s, const std::vector<Axis>& axes,
                 const std::vector<double>& values);

} // namespace rcsim::search
