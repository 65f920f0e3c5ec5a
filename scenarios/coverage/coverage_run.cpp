#include "scenarios/coverage/coverage_run.h"

#include "models/plumbing/config_error.h"
#include "scenarios/world/world.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <vector>

#ifndef RCSIM_COMM_FW_LISTINGS
#define RCSIM_COMM_FW_LISTINGS ""
#endif
#ifndef RCSIM_COMM_FW_SOURCES
#define RCSIM_COMM_FW_SOURCES ""
#endif

extern char** environ;

namespace rcsim::coverage {

namespace {

constexpr std::uint32_t kRomBase = debug::SymbolTable::rom_base;
constexpr std::uint32_t kRomSize = debug::SymbolTable::rom_end - debug::SymbolTable::rom_base;

std::vector<std::uint8_t> rom_bytes(World& world) {
    std::vector<std::uint8_t> rom(kRomSize);
    if (!world.ctl.comm.cpu.debug_read(kRomBase, rom.data(), rom.size())) rom.assign(kRomSize, 0);
    return rom;
}

} // namespace

CoverageRun::CoverageRun(World& world, CodeMap map)
    : map_(std::move(map)), counters_(kRomBase, rom_bytes(world)), next_(world.ctl.comm.cpu.step_observer()) {
    // Alone, a counter: the fast-forward may skip boundaries and say which. Another observer
    // needs each one executed, so then none is skipped.
    world.ctl.comm.cpu.set_step_observer(&CoverageRun::on_step, this, next_.first ? nullptr : &CoverageRun::on_skipped);
}

void CoverageRun::on_skipped(void* self, const i8086::Boundary* b, std::size_t n, std::uint64_t times) {
    static_cast<CoverageRun*>(self)->counters_.skipped(b, n, times);
}

bool CoverageRun::on_step(void* self, const i8086::Cpu& cpu) {
    auto* me = static_cast<CoverageRun*>(self);
    me->counters_.step(cpu);
    // Counted before the next observer may stop here: when it resumes, the core executes this
    // instruction without calling the hook again (i8086::StepHook), so it is counted once.
    return me->next_.first ? me->next_.first(me->next_.second, cpu) : false;
}

std::string CoverageRun::finish(const std::filesystem::path& dir) {
    const Tracefile t = counters_.tracefile(map_);
    write_tracefile_to(dir / "coverage.info", t);
    const bool html = run_genhtml(dir / "coverage.info", dir / "coverage");
    return coverage_section_html(t, html ? "coverage/index.html" : "");
}

CodeMap run_code_map(const debug::RomSymbols& symbols, const std::string& rom, const std::filesystem::path& dir) {
    if (symbols.built_firmware()) {
        const std::filesystem::path listings = RCSIM_COMM_FW_LISTINGS, sources = RCSIM_COMM_FW_SOURCES;
        return firmware_code_map({{sources / "crt0.s", listings / "crt0.lst"}, {sources / "isr.s", listings / "isr.lst"}},
                                 {sources / "main.c", sources / "hw.c"}, symbols.table);
    }
    if (symbols.table.empty())
        throw ConfigError("--coverage: the ROM " + rom + " has no symbols: give its map with --symbols FILE (docs/tools.md \"Coverage\")");
    return symbol_code_map(symbols.table, kRomBase, kRomBase + kRomSize, dir / "coverage_rom.txt");
}

bool run_genhtml(const std::filesystem::path& info, const std::filesystem::path& html_dir) {
    std::filesystem::create_directories(html_dir);
    const std::string log = (html_dir / "genhtml.log").string(), out = html_dir.string(), in = info.string();
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    std::vector<std::string> args = {"genhtml", "--quiet", "--branch-coverage", "--function-coverage",
                                     "--output-directory", out, in};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int rc = posix_spawnp(&pid, "genhtml", &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) { // not installed: the table in report.html is all there is
        std::filesystem::remove_all(html_dir);
        return false;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 && std::filesystem::exists(html_dir / "index.html");
}

} // namespace rcsim::coverage
