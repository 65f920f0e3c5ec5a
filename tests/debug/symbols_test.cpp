// Symbol tables (scenarios/debug/symbols.h): the three formats, lookups, and every malformed line
// named by file:line.
#include "scenarios/debug/symbols.h"

#include "comm_fw_symbols.h" // generated from the same map by comm_fw_mkrom

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <unistd.h>

namespace rcsim::debug {
namespace {

using testing::HasSubstr;
using Kind = Symbol::Kind;

// One file per test (CTest runs the tests of this file in parallel processes).
std::string write(const std::string& text) {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    const std::string path = testing::TempDir() + "rcsim_sym_" + info->name() + "_" + std::to_string(getpid());
    std::ofstream(path) << text;
    return path;
}

std::string error_of(const std::string& text, SymbolTable (*load)(const std::string&)) {
    const std::string path = write(text);
    try {
        load(path);
    } catch (const SymbolError& e) {
        return e.what();
    }
    return "(no error)";
}

SymbolTable load_any(const std::string& p) { return SymbolTable::load(p); }
SymbolTable load_ld86(const std::string& p) { return SymbolTable::load_ld86_map(p); }
SymbolTable load_nasm(const std::string& p) { return SymbolTable::load_nasm_map(p); }

// ---- the built firmware's ld86 map against comm_fw_mkrom's independent reading of it ----

TEST(Symbols, Ld86MapOfTheBuiltFirmwareMatchesTheGeneratedHeader) {
    const auto table = SymbolTable::load_ld86_map(RCSIM_COMM_FW_MAP);
    ASSERT_EQ(table.size(), std::size(comm_fw::symbols));
    for (const auto& s : comm_fw::symbols) {
        const Symbol* got = table.find(s.name);
        ASSERT_NE(got, nullptr) << s.name;
        EXPECT_EQ(got->address, s.linear) << s.name;
        EXPECT_EQ(got->kind, s.code ? Kind::code : Kind::data) << s.name;
    }
    // rs232_isr runs to the next global code symbol (its local labels do not cut it).
    std::uint32_t next = comm_fw::rom_base + comm_fw::code_bytes;
    for (const auto& s : comm_fw::symbols)
        if (s.code && s.linear > comm_fw::code::rs232_isr) next = std::min(next, s.linear);
    const Symbol* isr = table.find("rs232_isr");
    ASSERT_NE(isr, nullptr);
    EXPECT_EQ(isr->size, next - comm_fw::code::rs232_isr);
    EXPECT_EQ(table.containing(comm_fw::code::rs232_isr), isr);
    EXPECT_EQ(table.containing(next - 1), isr);
    EXPECT_NE(table.containing(next), isr);
    EXPECT_EQ(table.find("_rs232_isr"), nullptr); // bcc's underscore is dropped
    EXPECT_EQ(table.find("__segoff"), nullptr);   // linker symbols bound regions, name nothing
}

// ---- ld86 -M by hand ----

// Code at F0000 + value; DATA_SEG = 0x40 puts segment 3 at 0x400 + value. Sizes: start to _f
// (0x10), _f to the end of code (__segoff 0x2 paragraphs = 0x20: 0x20 - 0x10); _v to _w (4), _w
// to __end (0xA - 4 = 6). Locals (r) and absolutes (a) are not symbols.
const char* const ld86_map =
    "                crt0                 start  0  00000000  R\n"
    "                crt0              DATA_SEG  0  00000040  a\n"
    "                crt0                 local  0  00000004  r\n"
    "                main                    _f  0  00000010  R\n"
    "                crt0              __segoff  0  00000002  R\n"
    "                main                    _v  3  00000000  R\n"
    "                main                    _w  3  00000004  R C\n"
    "                crt0                 __end  3  0000000a  R\n"
    "Total memory used: 00000100\n";

TEST(Symbols, Ld86MapPlacesCodeAndDataAndSizesThem) {
    const auto table = SymbolTable::load(write(ld86_map));
    ASSERT_EQ(table.size(), 4u);
    EXPECT_EQ(table.find("start")->address, 0xF0000u);
    EXPECT_EQ(table.find("start")->size, 0x10u);
    EXPECT_EQ(table.find("f")->address, 0xF0010u);
    EXPECT_EQ(table.find("f")->size, 0x10u);
    EXPECT_EQ(table.find("v")->address, 0x400u);
    EXPECT_EQ(table.find("v")->kind, Kind::data);
    EXPECT_EQ(table.find("v")->size, 4u);
    EXPECT_EQ(table.find("w")->size, 6u);
    EXPECT_EQ(table.find("local"), nullptr);
    EXPECT_EQ(table.containing(0xF0004)->name, "start");
    EXPECT_EQ(table.containing(0x409)->name, "w");
    EXPECT_EQ(table.containing(0x40A), nullptr);
    EXPECT_EQ(table.containing(0xF0020), nullptr);
}

TEST(Symbols, Ld86MapWithoutDataSegLoadsCodeOnlyUnlessTheLayoutSaysWhere) {
    std::string map = ld86_map;
    map.erase(map.find("                crt0              DATA_SEG"), 60);
    const std::string path = write(map);
    EXPECT_EQ(SymbolTable::load_ld86_map(path).find("v"), nullptr);
    Ld86Layout layout;
    layout.data_base = 0x2000;
    EXPECT_EQ(SymbolTable::load_ld86_map(path, layout).find("v")->address, 0x2000u);
}

TEST(Symbols, Ld86MapErrorsNameTheLine) {
    auto ld = [](const std::string& line) {
        return error_of(std::string("  crt0 start 0 00000000 R\n") + line + "\n", &load_ld86);
    };
    EXPECT_THAT(ld("  m x 0 0000zz10 R"), HasSubstr(":2: bad value '0000zz10'"));
    EXPECT_THAT(ld("  m x 03 00000010 R"), HasSubstr(":2: bad segment '03'"));
    EXPECT_THAT(ld("  m x 0 00000010 Q"), HasSubstr(":2: bad flags 'Q'"));
    EXPECT_THAT(ld("  m x 0 00000010"), HasSubstr(":2: not an ld86 -M line"));
    EXPECT_THAT(ld("  m x 1 00000010 R"), HasSubstr(":2: symbol 'x' in segment 1"));
    EXPECT_THAT(ld("  m start 0 00000010 R"), HasSubstr(":2: duplicate symbol 'start'"));
}

// ---- nasm's map, from a real nasm run (symbols_sample.asm) ----

TEST(Symbols, NasmMapFromARealAssembly) {
    const auto table = SymbolTable::load(RCSIM_SYMBOLS_SAMPLE_MAP);
    ASSERT_EQ(table.size(), 5u);
    // The sizes from the source's comments: entry 3 bytes, helper 4, table 5 (to the section's
    // end at offset 0xC); counter resw 1, flags resb 1 (to the end of .bss, 0x403).
    const struct { const char* name; std::uint32_t address, size; Kind kind; } want[] = {
        {"entry", 0xF0000, 3, Kind::code},  {"helper", 0xF0003, 4, Kind::code},
        {"table", 0xF0007, 5, Kind::code},  {"counter", 0x400, 2, Kind::data},
        {"flags", 0x402, 1, Kind::data},
    };
    for (const auto& w : want) {
        const Symbol* s = table.find(w.name);
        ASSERT_NE(s, nullptr) << w.name;
        EXPECT_EQ(s->address, w.address) << w.name;
        EXPECT_EQ(s->size, w.size) << w.name;
        EXPECT_EQ(s->kind, w.kind) << w.name;
    }
    EXPECT_EQ(table.containing(0xF0006)->name, "helper");
    EXPECT_EQ(table.containing(0xF000C), nullptr);
}

TEST(Symbols, NasmMapErrorsNameTheLine) {
    const std::string head = "- NASM Map file ---\n\n-- Symbols ---\n\n---- Section .text ---\n\nReal Virtual Name\n";
    EXPECT_THAT(error_of(head + "  0  0  a b\n", &load_nasm), HasSubstr(":8: not a 'Real Virtual Name'"));
    EXPECT_THAT(error_of(head + "  g  0  a\n", &load_nasm), HasSubstr(":8: bad address 'g'"));
    EXPECT_THAT(error_of(head + "  0  0  9a\n", &load_nasm), HasSubstr(":8: bad symbol name '9a'"));
    EXPECT_THAT(error_of("hello\n", &load_nasm), HasSubstr(":1: not a nasm map file"));
}

// ---- the simple text format ----

TEST(Symbols, TextFormatAddressesSizesAndKinds) {
    const auto table = SymbolTable::load(write(
        "# rcsim symbols\n"
        "reset    0xFFFF0  5          # the reset stub\n"
        "main     F000:0100           # F0000 + 0100, runs to `work`\n"
        "work     F010:0010  0x20     # F0100 + 0010 = F0110, 32 bytes\n"
        "counter  0040:0002           # data (outside the ROM), the last data symbol: a label\n"
        "buffer   0x1000     16  data\n"
        "\n"
        "vec      0xF0200    2   data # a table in the ROM\n"));
    ASSERT_EQ(table.size(), 6u);
    EXPECT_EQ(table.find("main")->address, 0xF0100u);
    EXPECT_EQ(table.find("main")->size, 0x10u);
    EXPECT_EQ(table.find("work")->address, 0xF0110u);
    EXPECT_EQ(table.find("work")->size, 0x20u);
    EXPECT_EQ(table.find("reset")->size, 5u);
    EXPECT_EQ(table.find("counter")->address, 0x402u);
    EXPECT_EQ(table.find("counter")->kind, Kind::data);
    EXPECT_EQ(table.find("counter")->size, 0x1000u - 0x402u); // up to `buffer`
    EXPECT_EQ(table.find("buffer")->size, 16u);
    EXPECT_EQ(table.find("vec")->kind, Kind::data);
    EXPECT_EQ(table.containing(0xF012F)->name, "work");
    EXPECT_EQ(table.containing(0xF0130), nullptr);
    EXPECT_EQ(table.containing(0xFFFF4)->name, "reset");
    // symbols() is sorted by address
    EXPECT_TRUE(std::is_sorted(table.symbols().begin(), table.symbols().end(),
                               [](const Symbol& a, const Symbol& b) { return a.address < b.address; }));
}

TEST(Symbols, TextFormatErrorsNameTheLine) {
    auto text = [](const std::string& line) { return error_of("ok 0xF0000\n" + line + "\n", &load_any); };
    EXPECT_THAT(text("x"), HasSubstr(":2: missing ADDRESS"));
    EXPECT_THAT(text("x 0xF0000 1 code extra"), HasSubstr(":2: too many fields"));
    EXPECT_THAT(text("9x 0xF0000"), HasSubstr(":2: bad symbol name '9x'"));
    EXPECT_THAT(text("x F0000"), HasSubstr(":2: bad address 'F0000'"));
    EXPECT_THAT(text("x F0000:0"), HasSubstr(":2: bad address 'F0000:0'"));
    EXPECT_THAT(text("x 0x1000000"), HasSubstr(":2: bad address '0x1000000'"));
    EXPECT_THAT(text("x 0x110000"), HasSubstr(":2: address '0x110000' beyond"));
    EXPECT_THAT(text("x 0xF0010 -1"), HasSubstr(":2: bad size '-1'"));
    EXPECT_THAT(text("x 0xF0010 4 text"), HasSubstr(":2: bad kind 'text'"));
    EXPECT_THAT(text("ok 0xF0010"), HasSubstr(":2: duplicate symbol 'ok'"));
    EXPECT_THAT(error_of("", &load_any), HasSubstr("(no error)")); // an empty file is an empty table
    EXPECT_THAT(error_of("", [](const std::string&) { return SymbolTable::load("/nonexistent/x.sym"); }),
                HasSubstr("/nonexistent/x.sym: cannot open"));
}

} // namespace
} // namespace rcsim::debug
