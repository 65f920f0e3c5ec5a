// rcsim — `rcsim run --gdb` (gdb_run.h).
#include "scenarios/cli/gdb_run.h"

#include "scenarios/world/world.h"
#include "scenarios/debug/elf_symbols.h"
#include "scenarios/debug/gdb_script.h"
#include "scenarios/debug/rom_symbols.h"
#include "scenarios/report/output.h"
#include "models/plumbing/config_error.h"

#include <filesystem>
#include <fstream>
#include <ostream>

namespace rcsim::debug {

GdbRun::GdbRun(const GdbOptions& gdb, const Scenario& s, RunOptions& opt, std::ostream& out, std::ostream& log)
    : out_(out), log_(log) {
    if (s.has_motion) throw ConfigError(s.file, 0, "--gdb: a motion scenario runs no 8086 to debug");
    config_.set_listen(gdb.listen);
    config_.wait = gdb.wait;
    // The ROM the run loads (the option's, the scenario's, else the built firmware: "").
    symbols_ = rom_symbols(opt.rom ? *opt.rom : s.rom, gdb.symbols).table;
    if (symbols_.empty()) {
        log_ << "gdb: no symbols for this ROM (--symbols FILE gives them)" << std::endl;
    } else if (opt.out_dir.empty()) {
        log_ << "gdb: " << symbols_.size() << " symbols; give --out DIR to get DIR/symbols.elf for gdb" << std::endl;
    } else {
        const std::string elf = (std::filesystem::path(opt.out_dir) / "symbols.elf").string();
        prepare_out_dir(opt.out_dir);
        try {
            write_elf(symbols_, elf);
        } catch (const SymbolError& e) {
            throw ConfigError(e.what());
        }
        // The unwinder gdb needs for bt, up and finish on the 8086 (rcsim_gdb.py).
        const std::string script = (std::filesystem::path(opt.out_dir) / "rcsim-gdb.py").string();
        std::ofstream file(script);
        if (!(file << kGdbUnwinderScript).flush()) throw ConfigError(script, 0, "cannot write the gdb script");
        out_ << "gdb: symbols in " << elf << " (in gdb: file " << elf << ", then source " << script << ")" << std::endl;
    }
    opt.on_world = [this](World& world) {
        stub_ = std::make_unique<GdbStub>(config_, world.ctl.comm, world.pacer.get(), log_);
        out_ << "gdb: listening on " << stub_->endpoint()
             << (config_.wait ? " (waiting for the debugger before the first instruction)" : "") << std::endl;
    };
}

void GdbRun::finish(int exit_code) {
    if (stub_) stub_->finish(exit_code);
}

} // namespace rcsim::debug
