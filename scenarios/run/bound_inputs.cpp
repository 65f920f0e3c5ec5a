// rcsim — the static bound's inputs from a run. See bound_inputs.h.
#include "scenarios/run/bound_inputs.h"

#include "dpram/idt7130.h"
#include "models/plumbing/config_error.h"
#include "models/rom_image.h"
#include "scenarios/debug/rom_symbols.h"
#include "scenarios/world/world.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#ifndef RCSIM_COMM_FW_ANNOTATIONS
#define RCSIM_COMM_FW_ANNOTATIONS ""
#endif

namespace rcsim {

namespace {
constexpr std::size_t kTableBytes = 0x400; // 256 vectors of IP, CS
constexpr unsigned kIcw2 = 0x20;           // the firmware's ICW2: IR n is vector 0x20 + n (docs/system.md §3.3)
} // namespace

VectorCapture::VectorCapture(World& world) : world_(world) {
    i8086::Cpu& core = world.ctl.comm.cpu.core();
    previous_ = core.if_hook();
    previous_context_ = core.if_hook_context();
    core.set_if_hook(&VectorCapture::on_if, this);
}

void VectorCapture::on_if(void* self, const i8086::IfChange& change) {
    auto* me = static_cast<VectorCapture*>(self);
    if (me->previous_) me->previous_(me->previous_context_, change);
    if (me->captured_ || !change.enabled) return;
    const std::vector<std::uint8_t>& ram = me->world_.ctl.comm.ram();
    me->table_.assign(ram.begin(), ram.begin() + static_cast<long>(std::min(kTableBytes, ram.size())));
    me->table_.resize(kTableBytes, 0);
    me->captured_ = true;
}

std::vector<bound::Source> sources_from_table(const std::vector<std::uint8_t>& table) {
    static const char* const kNames[] = {"rs232_0", "rs232_1", "rs232_2", "dpram"}; // IR0..IR3
    std::vector<bound::Source> sources;
    for (unsigned ir = 0; ir < 4; ++ir) {
        bound::Source s;
        s.name = kNames[ir];
        s.vector = static_cast<std::uint8_t>(kIcw2 + ir);
        const std::size_t at = 4u * s.vector;
        s.ip = static_cast<std::uint16_t>(table[at] | table[at + 1] << 8);
        s.cs = static_cast<std::uint16_t>(table[at + 2] | table[at + 3] << 8);
        sources.push_back(s);
    }
    return sources;
}

i8086::WaitBounds board_waits(const ControllerConfig& board, std::string& reason) {
    const CommBoardConfig& c = board.comm;
    // The DP-RAM's BUSY at its worst for the 8086 (the left port, the later of the two): the main
    // CPU's cycle that wins the location ends at most max(its cycle, a cycle it itself waited
    // BUSY in) after our T1; the location is ours tBDA after, our read data tBDD (a write held
    // tWH) later; we wait only if that is past our T3 (dpram/README.md "BUSY arbitration").
    const Idt7130::BusyTiming t = Idt7130::grade_timing(board.dpram_speed_grade_ns);
    const double t_l = 1e9 / double(c.cpu_hz), t_r = 1e9 / double(board.main.bus_clock_hz); // ns
    const double n_l = Idt7130::PortTiming{}.cycle_clocks, n_r = board.main.access_cycles;
    const double bda = t.t_bda.to_seconds() * 1e9, bdd = t.t_bdd.to_seconds() * 1e9, wh = t.t_wh.to_seconds() * 1e9;
    const double winner_end = std::max(n_r * t_r, bda + bdd + t_r);
    const double done = winner_end + bda + std::max(bdd, wh);
    const double data_end = (n_l - 1) * t_l;
    const unsigned busy = static_cast<unsigned>(std::ceil(std::max(0.0, done - data_end) / t_l - 1e-9));
    i8086::WaitBounds w;
    w.code = c.rom_wait;
    w.data = std::max({c.ram_wait, c.rom_wait, c.dpram_wait + busy});
    w.io = c.io_wait;
    std::ostringstream os;
    os << "code: ROM " << c.rom_wait << "; data: max(RAM " << c.ram_wait << ", ROM " << c.rom_wait << ", DP-RAM "
       << c.dpram_wait << " + BUSY " << busy << "); io " << c.io_wait << ". BUSY: the main CPU's " << n_r
       << "-clock cycle at " << board.main.bus_clock_hz / 1e6 << " MHz and the " << board.dpram_speed_grade_ns
       << " ns grade (tBDA " << bda << " ns, tBDD " << bdd << " ns) give the location back " << done
       << " ns after the 8086's T1, its T3 ends at " << data_end << " ns: " << busy << " wait state(s)";
    reason = os.str();
    return w;
}

std::string annotations_file(const RomSource& rom, const std::string& annotations) {
    if (!annotations.empty()) return annotations;
    const std::string shipped = RCSIM_COMM_FW_ANNOTATIONS;
    if (!shipped.empty() && std::filesystem::exists(shipped) && debug::is_built_firmware(rom)) return shipped;
    return "";
}

std::vector<bound::Annotation> run_annotations(const RomSource& rom, const std::string& annotations,
                                               const debug::RomSymbols& symbols) {
    const std::string file = annotations_file(rom, annotations);
    if (file.empty()) return {};
    return bound::load_annotations(file, symbols.table);
}

bound::Inputs bound_inputs(const RomSource& rom, const debug::RomSymbols& symbols,
                           std::vector<bound::Annotation> annotations, const VectorCapture& vectors,
                           const ControllerConfig& board, double budget_us, const std::string& ran) {
    if (!vectors.captured()) throw ConfigError("the firmware never enabled interrupts in " + ran);
    bound::Inputs in;
    in.rom_base = board.comm.rom_base;
    in.rom = read_rom_image(rom, board.comm.rom_base, board.comm.rom_size).bytes;
    in.symbols = symbols.table;
    in.annotations = std::move(annotations);
    in.sources = sources_from_table(vectors.table());
    in.waits = board_waits(board, in.waits_reason);
    in.clock_mhz = double(board.comm.cpu_hz) / 1e6;
    in.budget_us = budget_us;
    in.pic_port = static_cast<std::uint8_t>(board.comm.pic_io_base);
    return in;
}

} // namespace rcsim
