// The as86 listing of the built firmware read back (scenarios/coverage/as86_listing.h) and the
// firmware's code map (code_map.h): instructions land on the source lines that isr.s has them on
// (found here by their text in isr.s), macro expansions on the macro's body lines.
#include "scenarios/coverage/as86_listing.h"
#include "scenarios/coverage/code_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>

using namespace rcsim::coverage;

namespace {

const std::string kListings = RCSIM_COMM_FW_LISTINGS, kSources = RCSIM_COMM_FW_SOURCES;

/// The 1-based lines of `file` whose text contains `needle`.
std::vector<unsigned> lines_with(const std::string& file, const std::string& needle) {
    std::ifstream in(file);
    std::string text;
    std::vector<unsigned> out;
    for (unsigned n = 1; std::getline(in, text); ++n)
        if (text.find(needle) != std::string::npos) out.push_back(n);
    return out;
}

unsigned instructions_on(const As86Listing& l, unsigned line) {
    return static_cast<unsigned>(std::count_if(l.instructions.begin(), l.instructions.end(),
                                               [line](const ListedInstruction& i) { return i.line == line; }));
}

} // namespace

TEST(As86Listing, AnInstructionIsOnItsSourceLine) {
    const As86Listing l = read_as86_listing(kListings + "/isr.lst");
    const auto n_break = lines_with(kSources + "/isr.s", "inc\tword ptr _n_break[si]");
    ASSERT_EQ(n_break.size(), 1u);
    EXPECT_EQ(instructions_on(l, n_break[0]), 1u);
    // A comment line and a label line hold no instruction.
    EXPECT_EQ(instructions_on(l, 1), 0u);
    const auto label = lines_with(kSources + "/isr.s", "line_status:");
    ASSERT_EQ(label.size(), 1u);
    EXPECT_EQ(instructions_on(l, label[0]), 0u);
    EXPECT_EQ(l.labels.count("line_status"), 1u);
}

TEST(As86Listing, AMacroBodyLineHoldsOneInstructionPerExpansion) {
    const As86Listing l = read_as86_listing(kListings + "/isr.lst");
    // RS232_ENTRY is expanded three times (ports 0-2), C_RESET twice, C_ENTRY four times.
    ASSERT_EQ(lines_with(kSources + "/isr.s", "RS232_ENTRY(").size(), 3u);
    const auto gir = lines_with(kSources + "/isr.s", "in\tal,?2+U_GIR");
    ASSERT_FALSE(gir.empty());
    EXPECT_EQ(instructions_on(l, gir[0]), 3u);
    ASSERT_EQ(lines_with(kSources + "/isr.s", "C_RESET(").size(), 2u);
    ASSERT_EQ(lines_with(kSources + "/isr.s", "C_ENTRY(").size(), 4u);
    const auto call = lines_with(kSources + "/isr.s", "call\t?2"); // C_RESET's body, then C_ENTRY's
    ASSERT_EQ(call.size(), 2u);
    EXPECT_EQ(instructions_on(l, call[0]), 2u);
    EXPECT_EQ(instructions_on(l, call[1]), 4u);
}

TEST(As86Listing, NotAListingIsAnErrorNamingTheFile) {
    try {
        read_as86_listing(kSources + "/isr.s");
        FAIL() << "no error";
    } catch (const std::exception& e) {
        EXPECT_EQ(std::string(e.what()), kSources + "/isr.s: not an as86 listing (no numbered rows)");
    }
}

TEST(FirmwareCodeMap, TheHandlersAndCFunctionsAreOnTheirDefinitionLines) {
    const auto symbols = rcsim::debug::SymbolTable::load_ld86_map(RCSIM_COMM_FW_MAP);
    const CodeMap m = firmware_code_map({{kSources + "/crt0.s", kListings + "/crt0.lst"}, {kSources + "/isr.s", kListings + "/isr.lst"}},
                                        {kSources + "/main.c", kSources + "/hw.c"}, symbols);
    auto fn = [&m](const std::string& name) {
        for (const CodeFunction& f : m.functions)
            if (f.name == name) return f;
        ADD_FAILURE() << "no function " << name;
        return CodeFunction{};
    };
    const auto dpram = lines_with(kSources + "/isr.s", "_isr_dpram:");
    ASSERT_EQ(dpram.size(), 1u);
    EXPECT_EQ(m.files[fn("isr_dpram").file], kSources + "/isr.s");
    EXPECT_EQ(fn("isr_dpram").line, dpram[0] + 1) << "the first instruction after the label";
    const auto main_def = lines_with(kSources + "/main.c", "main(");
    ASSERT_FALSE(main_def.empty());
    EXPECT_EQ(m.files[fn("main").file], kSources + "/main.c");
    EXPECT_NE(std::find(main_def.begin(), main_def.end(), fn("main").line), main_def.end());
}
