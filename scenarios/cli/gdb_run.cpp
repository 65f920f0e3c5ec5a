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

namespace {

/// Where gdb connects for a stub listening at `endpoint` ("ADDRESS:PORT"): the loopback for a
/// wildcard address, IPv6 in brackets.
std::string connect_address(const std::string& endpoint) {
    const auto colon = endpoint.rfind(':');
    std::string host = endpoint.substr(0, colon);
    const std::string port = endpoint.substr(colon + 1);
    if (host == "0.0.0.0") host = "127.0.0.1";
    if (host == "::") host = "::1";
    return host.find(':') != std::string::npos ? "[" + host + "]:" + port : host + ":" + port;
}

void write_text(const std::filesystem::path& path, const std::string& text) {
    std::ofstream file(path);
    if (!(file << text).flush()) throw ConfigError(path.string(), 0, "cannot write the file for gdb");
}

} // namespace

GdbRun::GdbRun(const GdbOptions& gdb, const Scenario& s, RunOptions& opt, std::ostream& out, std::ostream& log)
    : out_(out), log_(log) {
    if (s.has_motion) throw ConfigError(s.file, 0, "--gdb: a motion scenario runs no 8086 to debug");
    config_.set_listen(gdb.listen);
    config_.wait = gdb.wait;
    // The ROM the run loads (the option's, the scenario's, else the built firmware: "").
    RomSymbols rom = rom_symbols(opt.rom ? *opt.rom : s.rom, gdb.symbols);
    symbols_ = std::move(rom.table);
    if (symbols_.empty()) log_ << "gdb: no symbols for this ROM (--symbols FILE gives them)" << std::endl;
    if (!opt.out_dir.empty()) {
        const std::filesystem::path dir = opt.out_dir;
        prepare_out_dir(opt.out_dir);
        if (!symbols_.empty()) {
            try {
                write_elf(symbols_, (dir / "symbols.elf").string(), rom.declarations);
            } catch (const SymbolError& e) {
                throw ConfigError(e.what());
            }
        }
        // The unwinder gdb needs for bt, up and finish on the 8086 (rcsim_gdb.py).
        write_text(dir / "rcsim-gdb.py", kGdbUnwinderScript);
    }
    opt.on_world = [this, dir = opt.out_dir](World& world) {
        stub_ = std::make_unique<GdbStub>(config_, world.ctl.comm, world.pacer.get(), log_);
        if (!dir.empty()) write_command_file(dir);
        out_ << "gdb: listening on " << stub_->endpoint()
             << (config_.wait ? " (waiting for the debugger before the first instruction)" : "") << std::endl;
        if (!dir.empty())
            out_ << "gdb: to debug: gdb -x " << (std::filesystem::path(dir) / kCommandFile).string() << std::endl;
    };
}

// DIR/rcsim.gdb: what `gdb -x` needs to debug this run, with absolute paths so that gdb may
// start in any folder.
void GdbRun::write_command_file(const std::string& dir) const {
    const std::filesystem::path abs = std::filesystem::absolute(dir);
    std::string text = "# Written by rcsim run --gdb for this run: gdb -x THIS_FILE (docs/tools.md \"gdb\").\n"
                       "# gdb's kill ends the run as SIGTERM does (reports written, exit 143); detach leaves it running.\n";
    text += symbols_.empty() ? "# no symbols for this ROM (rcsim run --symbols FILE gives them)\n"
                             : "file " + (abs / "symbols.elf").string() + "\n";
    text += "source " + (abs / "rcsim-gdb.py").string() + "\n";
    text += "target remote " + connect_address(stub_->endpoint()) + "\n";
    write_text(abs / kCommandFile, text);
}

void GdbRun::finish(int exit_code) {
    if (stub_) stub_->finish(exit_code);
}

} // namespace rcsim::debug
