// rcsim — the code symbols the latency causes name addresses with (report.json
// "interrupts".SOURCE."worst", docs/scenarios.md "Latency causes").
#pragma once

#include "scenarios/debug/symbols.h"
#include "scenarios/verdict/latency_causes.h"


namespace rcsim {

/// The ROM's symbols (the run's, debug::rom_symbols) as the causes name an address: "name" for
/// an address a code symbol starts at, "name+0x1C" inside one, "" elsewhere. Empty (addresses
/// only) when the table is.
SymbolOf cause_symbols(debug::SymbolTable table);

} // namespace rcsim
