// The static bound on the built firmwares (scenarios/bound/bound.h): the shipped ROM keeps the
// rule on every path; the frozen all-C ROM does not, on its RS-232 handler.
#include "models/plumbing/config_error.h"
#include "scenarios/bound/bound.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>

using namespace rcsim;
using namespace rcsim::bound;

namespace {

std::vector<std::uint8_t> read(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/// The firmware's vectors 0x20..0x23 as crt0.s installs them (CS = F000, the handlers' offsets).
Inputs firmware(const std::string& rom, const std::string& map, const std::string& annotations) {
    Inputs in;
    in.rom = read(rom);
    in.symbols = debug::SymbolTable::load_ld86_map(map);
    if (!annotations.empty()) in.annotations = load_annotations(annotations, in.symbols);
    const char* names[] = {"rs232_0", "rs232_1", "rs232_2", "dpram"};
    const char* handlers[] = {"isr_port0", "isr_port1", "isr_port2", "isr_dpram"};
    for (int n = 0; n < 4; ++n) {
        const debug::Symbol* s = in.symbols.find(handlers[n]);
        if (!s) throw std::runtime_error(std::string("no symbol ") + handlers[n]);
        in.sources.push_back({names[n], std::uint8_t(0x20 + n), 0xF000, std::uint16_t(s->address - 0xF0000)});
    }
    in.waits = {1, 1, 1, 0};
    in.budget_us = 381.9;
    return in;
}

} // namespace

TEST(BoundFirmware, TheShippedFirmwareKeepsTheRuleOnEveryPath) {
    const Result r = analyse(firmware(RCSIM_COMM_FW_ROM, RCSIM_COMM_FW_MAP, RCSIM_BOUND_ANNOTATIONS));
    EXPECT_TRUE(r.fits()) << describe_over_budget(r);
    for (const auto& [name, b] : r.sources) {
        EXPECT_LE(b.blocking_us, r.budget_us) << name;
        EXPECT_LE(b.blocking_clocks, b.service_clocks) << name;
        for (const Loop& l : b.loops) EXPECT_FALSE(l.reason.empty()) << name << " " << l.where;
    }
    // docs/firmware.md: the RS-232 handlers keep IF = 0 to their IRET; the DP-RAM handler sends its
    // EOI and sets IF = 1 before its copy, so only its ends keep other requests waiting.
    for (const char* port : {"rs232_0", "rs232_1", "rs232_2"}) {
        const SourceBound& b = r.sources.at(port);
        EXPECT_FALSE(b.reenables) << port;
        EXPECT_EQ(b.blocking_clocks, b.service_clocks) << port;
    }
    const SourceBound& dpram = r.sources.at("dpram");
    EXPECT_TRUE(dpram.reenables);
    EXPECT_LT(dpram.blocking_clocks, dpram.service_clocks);
    // The chunk copy's LOOPNE runs CHUNK = 339 times at most, from CX = CHUNK (fw.h), inferred.
    EXPECT_TRUE(std::any_of(dpram.loops.begin(), dpram.loops.end(),
                            [](const Loop& l) { return l.iterations == 339 && l.reason.find("CX <= 339") == 0; }));
    // The main loop's IF = 0 stretches (irq_off ... irq_restore) are bounded too.
    EXPECT_GT(r.main_if0.clocks, 0u);
}

// The frozen all-C firmware (issue #45's counter-example): its RS-232 handler runs the port reset
// itself on a BREAK (port_reset -> uart_init inside the handler), far over the budget.
TEST(BoundFirmware, TheAllCFirmwareIsOverTheBudgetOnItsRs232Handler) {
    const Result r = analyse(firmware(RCSIM_COMM_FW_C_ROM, RCSIM_COMM_FW_C_MAP, RCSIM_BOUND_C_ANNOTATIONS));
    EXPECT_FALSE(r.fits());
    for (const char* port : {"rs232_0", "rs232_1", "rs232_2"}) {
        const SourceBound& b = r.sources.at(port);
        EXPECT_GT(b.blocking_us, r.budget_us) << port;
    }
    EXPECT_NE(describe_over_budget(r).find("rs232_0: blocking bound"), std::string::npos) << describe_over_budget(r);
}

// The firmware of c67a15e (issue #47): its RS-232 handler ran the port reset on a BREAK
// (port_reset -> uart_init inside it) and was seen to keep interrupts off for 1088 us. No sample
// showed it; the bound must.
TEST(BoundFirmware, TheBreakPathOfC67a15eIsBoundedAtLeastAtWhatItWasSeenToTake) {
    const std::string dir = RCSIM_BOUND_FIXTURES "/c67a15e/";
    const Result r = analyse(firmware(dir + "comm_fw.rom", dir + "comm_fw.map", dir + "bound.annotations"));
    for (const char* port : {"rs232_0", "rs232_1", "rs232_2"}) EXPECT_GE(r.sources.at(port).blocking_us, 1088.0) << port;
    EXPECT_FALSE(r.fits());
}
