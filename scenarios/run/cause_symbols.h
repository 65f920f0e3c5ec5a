// rcsim — the code symbols the latency causes name addresses with (report.json
// "interrupts".SOURCE."worst", docs/scenarios.md "Latency causes").
#pragma once

#include "scenarios/verdict/latency_causes.h"

#include <string>

namespace rcsim {

/// The ROM's symbols as the profiler finds them (trace::run_symbols: `file` if given, else the
/// built firmware's ld86 map when `rom` is the built firmware): "name" for an address a code
/// symbol starts at, "name+0x1C" inside one, "" elsewhere. Empty (addresses only) when there are
/// none or they cannot be read: a cause never fails a run.
SymbolOf cause_symbols(const std::string& file, const std::string& rom);

} // namespace rcsim
