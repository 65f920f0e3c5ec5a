// rcsim — the flame graph of a cycle profile (scenarios/trace/profiler.h) as SVG, drawn with the
// project's chart module (scenarios/report/svg.h), for report.html.
//
// The classic layout: the whole run at the bottom, the contexts (main, IR0, ...) above it, each
// function above its caller; a box's width is its clocks (self + callees) in that call path.
// Boxes narrower than half a pixel are left out (their clocks stay in their parent's width);
// every box has a tooltip with its clocks, share and microseconds.
#pragma once

#include "scenarios/trace/profiler.h"

#include <string>

namespace rcsim::trace {

std::string flame_graph_svg(const CycleProfiler& profile, double clock_hz, double width = 1100);

} // namespace rcsim::trace
