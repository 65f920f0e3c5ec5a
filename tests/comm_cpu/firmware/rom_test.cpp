// The communication firmware ROM image: size, reset vector, data image, symbol map/JSON/header.
#include "comm_fw_symbols.h"
#include "models/dpram_layout.h"
#include "tests/support/sc_test.h"
#include "tests/support/files.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fw = rcsim::comm_fw;

std::vector<std::uint8_t> rom() { return rcsim::test::slurp_bytes(RCSIM_COMM_FW_ROM); }

std::uint16_t word(const std::vector<std::uint8_t>& r, std::uint32_t off) {
    return std::uint16_t(r.at(off) | (r.at(off + 1) << 8));
}

TEST(FirmwareRom, IsExactly64KiB) {
    EXPECT_EQ(rom().size(), 65536u);
    EXPECT_STREQ(fw::rom_path, RCSIM_COMM_FW_ROM);
}

TEST(FirmwareRom, ResetVectorIsFarJumpToStart) {
    const auto r = rom();
    ASSERT_EQ(r.size(), 65536u);
    // physical FFFF0 = ROM offset FFF0: JMP FAR F000:start
    EXPECT_EQ(r[0xFFF0], 0xEA);
    const std::uint16_t ip = word(r, 0xFFF1), cs = word(r, 0xFFF3);
    EXPECT_EQ(cs, 0xF000);
    EXPECT_EQ(fw::rom_base + ip, fw::code::start);
    EXPECT_LT(ip, fw::code_bytes);
    // the start-up code begins with CLI (no interrupt before the vectors exist)
    EXPECT_EQ(r[ip], 0xFA);
    // nothing but the stub above the image
    for (std::uint32_t a = fw::code_bytes + fw::data_bytes; a < 0xFFF0; ++a)
        ASSERT_EQ(r[a], 0xFF) << "at " << a;
}

TEST(FirmwareRom, InitialisedDataFollowsTheCode) {
    const auto r = rom();
    ASSERT_EQ(r.size(), 65536u);
    // rxbuf[] is initialised data: the three 20 KB port buffers at DS:0C00, 5C00, AC00
    const std::uint32_t at = fw::code_bytes + (fw::data::rxbuf - fw::data_segment * 16u);
    EXPECT_EQ(word(r, at), 0x0C00);
    EXPECT_EQ(word(r, at + 2), 0x5C00);
    EXPECT_EQ(word(r, at + 4), 0xAC00);
    const std::uint32_t tx = fw::code_bytes + (fw::data::txbuf - fw::data_segment * 16u);
    EXPECT_EQ(word(r, tx), 0x0C00 + 0x2800);
    EXPECT_EQ(word(r, fw::rom_offset_of(fw::data::port_div)), 60);      // 9600 bps at 18.432 MHz
    EXPECT_EQ(r[fw::rom_offset_of(fw::data::port_lcr) + 2], 0x1B);      // 8E1
    EXPECT_EQ(word(r, fw::rom_offset_of(fw::data::tick_div)), 9216);   // 1 ms
    EXPECT_LE(fw::data::tick_div + 2, fw::data_end);
    const std::uint32_t ar = fw::code_bytes + (fw::data::area - fw::data_segment * 16u);
    // The firmware's area table agrees with the layout the main CPU uses (models/dpram_layout.h).
    EXPECT_EQ(word(r, ar + 2), rcsim::dpram_layout::data_addr(1));
    EXPECT_EQ(word(r, ar + 4), rcsim::dpram_layout::data_addr(2));
}

TEST(FirmwareRom, MapNamesTheIsrsAndTheMainLoop) {
    std::ifstream in(RCSIM_COMM_FW_MAP);
    ASSERT_TRUE(in) << RCSIM_COMM_FW_MAP;
    std::set<std::string> names;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ss(line);
        std::string module, name;
        if (ss >> module >> name) names.insert(name);
    }
    for (const char* s : {"_isr_port0", "_isr_port1", "_isr_port2", "_isr_dpram", "_isr_unexpected",
                          "_rs232_isr", "_dpram_isr", "_main_loop", "_main", "start", "_ticks", "_step"})
        EXPECT_TRUE(names.count(s)) << s;
}

TEST(FirmwareRom, JsonAndHeaderAgree) {
    std::ifstream in(RCSIM_COMM_FW_JSON);
    ASSERT_TRUE(in);
    const auto j = nlohmann::json::parse(in);
    EXPECT_EQ(j.at("rom_size").get<unsigned>(), 65536u);
    EXPECT_EQ(j.at("code_bytes").get<unsigned>(), fw::code_bytes);
    unsigned seen = 0;
    for (const auto& s : fw::symbols) {
        ASSERT_TRUE(j.at("symbols").contains(s.name)) << s.name;
        const auto& e = j.at("symbols").at(s.name);
        EXPECT_EQ(e.at("linear").get<std::uint32_t>(), s.linear) << s.name;
        EXPECT_EQ(e.at("kind").get<std::string>(), s.code ? "code" : "data") << s.name;
        if (s.code) {
            EXPECT_GE(s.linear, fw::rom_base) << s.name;
            EXPECT_LT(s.linear, fw::rom_base + fw::code_bytes) << s.name;
        } else {
            EXPECT_GE(s.linear, fw::data_segment * 16u) << s.name;
            EXPECT_LT(s.linear, fw::data_segment * 16u + 0x0800) << s.name; // below the stack
        }
        ++seen;
    }
    EXPECT_EQ(seen, j.at("symbols").size());
    EXPECT_GT(fw::code::isr_dpram, fw::code::isr_port0);
}

} // namespace
