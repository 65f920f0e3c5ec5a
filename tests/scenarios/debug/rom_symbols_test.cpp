// The one decision of a run's ROM symbols (scenarios/debug/rom_symbols.h): the user's file wins,
// the built firmware's map names the built firmware in any of its forms, any other ROM has none,
// and a bad file is one ConfigError naming it.
#include "scenarios/debug/rom_symbols.h"

#include "models/plumbing/config_error.h"
#include "tests/support/files.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace rcsim::debug {
namespace {

namespace fs = std::filesystem;
using Origin = RomSymbols::Origin;
using testing::HasSubstr;

// The built firmware's globals (comm_cpu/firmware): its RS-232 interrupt handler.
constexpr const char* kFirmwareRoutine = "rs232_isr";

std::string write_bytes(const std::string& name, const std::vector<std::uint8_t>& bytes) {
    const fs::path p = rcsim::test::scratch_dir() / name;
    std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    return p.string();
}

std::string config_error_of(const RomSource& rom, const std::string& symbols) {
    try {
        rom_symbols(rom, symbols);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(RomSymbols, TheBuiltFirmwareByDefaultAndByItsFileGetsItsMap) {
    for (const RomSource& rom : {RomSource{}, RomSource{RCSIM_COMM_FW_ROM, ""}}) {
        const RomSymbols s = rom_symbols(rom, "");
        EXPECT_EQ(s.origin, Origin::built_firmware) << rom.file;
        EXPECT_TRUE(s.built_firmware());
        EXPECT_EQ(s.file, RCSIM_COMM_FW_MAP);
        EXPECT_NE(s.table.find(kFirmwareRoutine), nullptr);
    }
}

TEST(RomSymbols, TheBuiltFirmwaresBytesElsewhereAreTheBuiltFirmware) {
    const std::vector<std::uint8_t> rom = rcsim::test::slurp_bytes(RCSIM_COMM_FW_ROM);
    ASSERT_EQ(rom.size(), 0x10000u);
    std::vector<std::uint8_t> even, odd;
    for (std::size_t i = 0; i < rom.size(); ++i) (i % 2 ? odd : even).push_back(rom[i]);
    const std::string copy = write_bytes("copy.rom", rom);
    EXPECT_TRUE(is_built_firmware(RomSource{copy, ""}));
    EXPECT_EQ(rom_symbols(RomSource{copy, ""}, "").origin, Origin::built_firmware);
    // Its even/odd EPROM pair (docs/tools.md "ROM images").
    const RomSource pair{write_bytes("even.bin", even), write_bytes("odd.bin", odd)};
    EXPECT_EQ(rom_symbols(pair, "").origin, Origin::built_firmware);
}

TEST(RomSymbols, AnotherRomHasNone) {
    std::vector<std::uint8_t> rom = rcsim::test::slurp_bytes(RCSIM_COMM_FW_ROM);
    rom[0xFFE0] ^= 0x01; // one byte of the padding: another ROM, whose addresses the map may not name
    for (const RomSource& other : {RomSource{write_bytes("patched.rom", rom), ""}, RomSource{RCSIM_COMM_FW_C_ROM, ""}}) {
        const RomSymbols s = rom_symbols(other, "");
        EXPECT_FALSE(is_built_firmware(other)) << other.file;
        EXPECT_EQ(s.origin, Origin::none) << other.file;
        EXPECT_TRUE(s.table.empty()) << other.file;
        EXPECT_EQ(s.file, "");
    }
}

TEST(RomSymbols, TheUsersFileWinsForAnyRom) {
    for (const RomSource& rom : {RomSource{}, RomSource{RCSIM_COMM_FW_C_ROM, ""}}) {
        const RomSymbols s = rom_symbols(rom, RCSIM_SYMBOLS_SAMPLE_MAP);
        EXPECT_EQ(s.origin, Origin::user);
        EXPECT_FALSE(s.built_firmware()) << "the built firmware's listings do not describe the user's symbols";
        EXPECT_EQ(s.file, RCSIM_SYMBOLS_SAMPLE_MAP);
        EXPECT_EQ(s.table.find(kFirmwareRoutine), nullptr);
        ASSERT_NE(s.table.find("entry"), nullptr);
        EXPECT_EQ(s.table.find("entry")->address, 0xF0000u) << "a nasm image's first byte at the ROM's";
    }
}

TEST(RomSymbols, FileAtSegLoadsTheImageThere) {
    const RomSymbols s = rom_symbols(RomSource{}, std::string(RCSIM_SYMBOLS_SAMPLE_MAP) + "@E000");
    ASSERT_NE(s.table.find("helper"), nullptr);
    EXPECT_EQ(s.table.find("helper")->address, 0xE0003u); // E000:0003 (symbols_sample.asm)
    EXPECT_EQ(summary(s).file, "symbols_sample.map@E000");
}

TEST(RomSymbols, ABadFileIsOneConfigErrorNamingIt) {
    const fs::path bad = rcsim::test::scratch_dir() / "bad.sym";
    std::ofstream(bad) << "start F000:0000\nbroken line with too many words here\n";
    EXPECT_THAT(config_error_of(RomSource{}, bad.string()), HasSubstr("--symbols: " + bad.string() + ":2: "));
    EXPECT_THAT(config_error_of(RomSource{}, "nothere.map"), HasSubstr("--symbols: nothere.map: cannot open"));
}

TEST(RomSymbols, TheSummarySaysWhose) {
    const RomSymbolsSummary built = summary(rom_symbols(RomSource{}, ""));
    EXPECT_EQ(built.origin, "built firmware");
    EXPECT_EQ(built.file, fs::path(RCSIM_COMM_FW_MAP).filename().string());
    EXPECT_GT(built.count, 0u);
    const RomSymbolsSummary none = summary(rom_symbols(RomSource{RCSIM_COMM_FW_C_ROM, ""}, ""));
    EXPECT_EQ(none.origin, "none");
    EXPECT_EQ(none.file, "");
    EXPECT_EQ(none.count, 0u);
    const RomSymbolsSummary user = summary(rom_symbols(RomSource{}, RCSIM_SYMBOLS_SAMPLE_MAP));
    EXPECT_EQ(user.origin, "--symbols");
    EXPECT_EQ(user.file, "symbols_sample.map");
}

} // namespace
} // namespace rcsim::debug
