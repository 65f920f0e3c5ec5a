#include "scenarios/debug/rom_symbols.h"

#include "models/plumbing/config_error.h"

#include <filesystem>
#include <system_error>

#ifndef RCSIM_COMM_FW_ROM
#define RCSIM_COMM_FW_ROM ""
#endif
#ifndef RCSIM_COMM_FW_MAP
#define RCSIM_COMM_FW_MAP ""
#endif
#ifndef RCSIM_COMM_FW_SOURCES
#define RCSIM_COMM_FW_SOURCES ""
#endif

namespace rcsim::debug {

namespace {

constexpr std::size_t kRomWindow = SymbolTable::rom_end - SymbolTable::rom_base;

bool same_file(const std::string& a, const std::string& b) {
    std::error_code ec;
    return std::filesystem::equivalent(a, b, ec) && !ec;
}

} // namespace

bool is_built_firmware(const RomSource& rom) {
    const std::string built = RCSIM_COMM_FW_ROM;
    if (built.empty()) return false; // a build without the firmware: nothing is it
    if (rom.file.empty()) return true;
    if (rom.odd.empty() && same_file(rom.file, built)) return true;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(built, ec)) return false;
    // By content, as the CPU sees it: a copy of the ROM elsewhere, or the same bytes in another
    // format, is still the firmware the map describes.
    return read_rom_image(rom, SymbolTable::rom_base, kRomWindow).bytes ==
           read_rom_image(RomSource{built, ""}, SymbolTable::rom_base, kRomWindow).bytes;
}

RomSymbols rom_symbols(const RomSource& rom, const std::string& symbols) {
    RomSymbols r;
    if (!symbols.empty()) {
        r.origin = RomSymbols::Origin::user;
        r.file = symbols;
        try {
            r.table = SymbolTable::load(symbols);
        } catch (const SymbolError& e) {
            throw ConfigError(std::string("--symbols: ") + e.what());
        }
        return r;
    }
    const std::string map = RCSIM_COMM_FW_MAP;
    if (map.empty() || !is_built_firmware(rom)) return r;
    r.origin = RomSymbols::Origin::built_firmware;
    r.file = map;
    try {
        r.table = SymbolTable::load_ld86_map(map);
    } catch (const SymbolError& e) {
        throw ConfigError(std::string("the built firmware's map: ") + e.what());
    }
    const std::filesystem::path src = RCSIM_COMM_FW_SOURCES;
    if (!src.empty())
        r.declarations = read_c_declarations({(src / "fw.h").string(), (src / "main.c").string(), (src / "hw.c").string()});
    return r;
}

RomSymbolsSummary summary(const RomSymbols& symbols) {
    RomSymbolsSummary s;
    switch (symbols.origin) {
    case RomSymbols::Origin::none: s.origin = "none"; break;
    case RomSymbols::Origin::user: s.origin = "--symbols"; break;
    case RomSymbols::Origin::built_firmware: s.origin = "built firmware"; break;
    }
    s.file = std::filesystem::path(symbols.file).filename().string();
    s.count = symbols.table.size();
    return s;
}

} // namespace rcsim::debug
