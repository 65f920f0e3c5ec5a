// rcsim — `rcsim run --gdb`: the symbols for gdb and the stub's place in a run (docs/tools.md).
#pragma once

#include "scenarios/debug/gdb_stub.h"
#include "scenarios/debug/symbols.h"
#include "scenarios/run/runner.h"
#include "scenarios/config/scenario.h"

#include <iosfwd>
#include <memory>
#include <string>

namespace rcsim::debug {

struct GdbOptions {
    std::string listen;  // --gdb [HOST:]PORT
    bool wait = false;   // --gdb-wait
    std::string symbols; // --symbols FILE[@SEG] ("" = debug::rom_symbols decides from the ROM)
};

/// Set up before run_scenario(): reads the ROM's symbols (debug::rom_symbols: the file named, or
/// the built firmware's map when the run's ROM is the built firmware), writes them as
/// OUT/symbols.elf (its data symbols typed from the C declarations), the unwinder as
/// OUT/rcsim-gdb.py, and makes `options.on_world` start the stub on the assembled board and write
/// OUT/rcsim.gdb, the command file `gdb -x` reads: it loads both and connects. Keep it alive across
/// run_scenario() and call finish() with its exit code. Throws ConfigError on bad input.
class GdbRun {
public:
    GdbRun(const GdbOptions& gdb, const Scenario& scenario, RunOptions& options, std::ostream& out,
           std::ostream& log);
    void finish(int exit_code);
    const SymbolTable& symbols() const { return symbols_; }
    static constexpr const char* kCommandFile = "rcsim.gdb";

private:
    void write_command_file(const std::string& dir) const;

    GdbStubConfig config_;
    SymbolTable symbols_;
    std::unique_ptr<GdbStub> stub_;
    std::ostream& out_;
    std::ostream& log_;
};

} // namespace rcsim::debug
