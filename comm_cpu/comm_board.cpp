#include "comm_cpu/comm_board.h"

#include "dpram/idt7130.h"
#include "models/plumbing/config_error.h"

#include <algorithm>

namespace rcsim {

namespace {
Uart82510::Config uart_config(const CommBoardConfig& c) {
    Uart82510::Config u;
    u.clock_hz = c.uart_clock_hz;
    return u;
}
} // namespace

CommBoard::CommBoard(sc_core::sc_module_name name, const CommBoardConfig& cfg)
    : sc_module(name), config(cfg), cpu("cpu", Clock(cfg.cpu_hz)), io("io", true), mem("mem"),
      pic("pic"),
      uart("uart", kPorts,
           [&cfg](const char* n, std::size_t) { return new Uart82510(n, uart_config(cfg)); }),
      uart_int("uart_int", kPorts), ram_(cfg.ram_size, 0), rom_(cfg.rom_size, 0xFF) {
    cpu.set_quantum(cfg.quantum);
    cpu.set_lookahead(cfg.lookahead);
    cpu.set_fast_sync(cfg.fast_sync);
    cpu.set_fast_forward(cfg.fast_forward);
    cpu.set_stable_reads(&io, &mem);
    cpu.set_stable_reads_enabled(cfg.stable_reads);
    cpu.set_slice_chain(cfg.slice_chain);
    cpu.map_memory({"ram", cfg.ram_base, cfg.ram_size, ram_.data(), cfg.ram_wait, true});
    cpu.map_memory({"rom", cfg.rom_base, cfg.rom_size, rom_.data(), cfg.rom_wait, false});

    cpu.io.bind(io.in);
    cpu.mem.bind(mem.in);
    cpu.inta.bind(pic.inta);
    cpu.intr(intr);
    cpu.nmi(nmi);
    pic.intr(intr);

    for (unsigned n = 0; n < kPorts; ++n) {
        io.out.bind(uart[n].bus);
        io.map(uart_io_address(n, 0), 2 * 8, n, uart[n].name(), cfg.io_wait);
        io.declare_stable(uart_io_address(n, 0), &uart[n]);
        uart[n].int_out(uart_int[n]);
        pic.ir[n](uart_int[n]);
    }
    io.out.bind(pic.bus);
    io.map(cfg.pic_io_base, 4, kPorts, pic.name(), cfg.io_wait);
    for (unsigned ir = kDpramIr + 1; ir < 8; ++ir) pic.ir[ir](unused_ir);
}

void CommBoard::connect_dpram(Idt7130& dpram, IrqLine& int_l) {
    mem.out.bind(dpram.left);
    mem.map(config.dpram_base, Idt7130::kSize, 0, dpram.name(), config.dpram_wait);
    mem.declare_stable(config.dpram_base, &dpram);
    pic.ir[kDpramIr](int_l);
}

void CommBoard::load_rom(const RomSource& source) {
    RomImage image = read_rom_image(source, config.rom_base, rom_.size());
    load_rom(image.bytes, source.file);
    rom_format_ = std::move(image.format);
}

void CommBoard::load_rom(const std::vector<std::uint8_t>& image, const std::string& what) {
    if (image.size() != rom_.size())
        throw ConfigError(what, 0, "ROM image is " + std::to_string(image.size()) + " bytes; the board's ROM is " +
                                       std::to_string(rom_.size()) + " bytes");
    std::copy(image.begin(), image.end(), rom_.begin()); // in place: the CPU holds a direct pointer
}

} // namespace rcsim
