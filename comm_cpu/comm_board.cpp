#include "comm_cpu/comm_board.h"

#include "dpram/idt7130.h"
#include "models/config_error.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

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
    pic.ir[kDpramIr](int_l);
}

namespace {
std::string rom_size_message(std::uintmax_t size, std::size_t rom_size) {
    return "ROM image is " + std::to_string(size) + " bytes; the board's ROM is " + std::to_string(rom_size) +
           " bytes (a raw image with the reset vector at FFFF:0000)";
}
} // namespace

void CommBoard::load_rom(const std::string& path) {
    namespace fs = std::filesystem;
    if (path.empty()) throw ConfigError("ROM image '': an empty path (give a file, or leave it out for the built firmware)");
    // Check what the path is before reading it: a device (/dev/zero) or a huge file would be read
    // whole first, and /proc files report a size of 0 but read as something else entirely.
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (fs::is_directory(st)) throw ConfigError(path, 0, "is a directory, not a ROM image");
    if (fs::exists(st) && !fs::is_regular_file(st)) throw ConfigError(path, 0, "is not a regular file (a ROM image)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ConfigError(path, 0, "cannot open ROM image");
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec || size != rom_.size()) throw ConfigError(path, 0, rom_size_message(ec ? 0 : size, rom_.size()));
    std::vector<std::uint8_t> image(rom_.size());
    in.read(reinterpret_cast<char*>(image.data()), static_cast<std::streamsize>(image.size()));
    if (in.gcount() != static_cast<std::streamsize>(image.size()) || in.peek() != std::char_traits<char>::eof())
        throw ConfigError(path, 0, "ROM image changed size while it was read, or cannot be read");
    load_rom(image, path);
}



void CommBoard::load_rom(const std::vector<std::uint8_t>& image, const std::string& what) {
    if (image.size() != rom_.size()) throw ConfigError(what, 0, rom_size_message(image.size(), rom_.size()));
    std::copy(image.begin(), image.end(), rom_.begin()); // in place: the CPU holds a direct pointer
}

} // namespace rcsim
