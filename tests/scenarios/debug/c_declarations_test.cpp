// The types of C variables for gdb (scenarios/debug/c_declarations.h, dwarf_types.h): the forms
// the firmware declares its globals in, what is skipped, and the type a symbol without a
// declaration gets from its size.
#include "scenarios/debug/c_declarations.h"
#include "scenarios/debug/dwarf_types.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>

namespace rcsim::debug {
namespace {

std::map<std::string, CType> parse(const std::string& text) {
    std::map<std::string, std::int64_t> defines;
    std::map<std::string, CType> out;
    parse_c_declarations(text, defines, out);
    return out;
}

TEST(CDeclarations, FormsOfTheFirmware) {
    const auto d = parse("#define NO_PORT 3\n#define TXQ 8 /* frames */\n"
                         "unsigned ticks;\n"
                         "unsigned rx_len[NO_PORT], rx_fwd[NO_PORT];\n"
                         "static unsigned char mb_head, mb_tail;\n"
                         "unsigned txq_len[NO_PORT][TXQ];\n"
                         "unsigned char *rxbuf[NO_PORT] = { (unsigned char *)0xC00, (unsigned char *)(0xC00 + 5) };\n"
                         "unsigned area[NO_PORT] = { 0 * 340, 1 * 340, 2 * 340 }, after = 1;\n"
                         "long big; signed char sc; char c; short s; int i;\n");
    ASSERT_EQ(d.count("ticks"), 1u);
    EXPECT_EQ(d.at("ticks").base, "unsigned int");
    EXPECT_EQ(d.at("ticks").size(), 2u); // bcc's int
    EXPECT_EQ(d.at("rx_len").dims, std::vector<std::uint32_t>{3});
    EXPECT_EQ(d.at("rx_fwd").size(), 6u);
    EXPECT_EQ(d.at("mb_tail").base, "unsigned char");
    EXPECT_EQ(d.at("mb_tail").size(), 1u);
    EXPECT_EQ(d.at("txq_len").dims, (std::vector<std::uint32_t>{3, 8}));
    EXPECT_EQ(d.at("txq_len").size(), 48u);
    EXPECT_TRUE(d.at("rxbuf").pointer);
    EXPECT_EQ(d.at("rxbuf").size(), 6u); // near pointers: 2 bytes each
    EXPECT_EQ(d.at("area").size(), 6u);
    EXPECT_EQ(d.at("after").base, "unsigned int"); // after an initialiser with commas in braces
    EXPECT_EQ(d.at("big").size(), 4u);
    EXPECT_TRUE(d.at("big").is_signed);
    EXPECT_EQ(d.at("sc").base, "signed char");
    EXPECT_EQ(d.at("c").base, "char");
    EXPECT_EQ(d.at("s").base, "short");
    EXPECT_EQ(d.at("i").base, "int");
    EXPECT_TRUE(d.at("i").is_signed);
}

TEST(CDeclarations, SkipsWhatIsNotAVariableOfFileScope) {
    const auto d = parse("void mb_post(unsigned char word)\n{\n    unsigned f = irq_off();\n    int inner;\n}\n"
                         "unsigned irq_off(void);\n"
                         "typedef unsigned word;\nword w;\n"
                         "struct s { int member; } sv;\n"
                         "unsigned bad[UNKNOWN], bad2[3 + 1];\n"
                         "char *msg = \"a; b { c\";\n"
                         "/* int commented; */ // int line_comment;\n"
                         "#asm\n int in_asm;\n#endasm\n"
                         "#define EXPR (1 + 2)\nunsigned by_expr[EXPR];\n"
                         "int last;\n");
    for (const char* gone : {"f", "inner", "mb_post", "irq_off", "word", "w", "member", "sv", "bad", "bad2",
                             "commented", "line_comment", "in_asm", "by_expr"})
        EXPECT_EQ(d.count(gone), 0u) << gone;
    EXPECT_TRUE(d.at("msg").pointer); // the string's ';' and '{' do not end or open anything
    EXPECT_EQ(d.at("last").base, "int");
}

TEST(CDeclarations, TheBuiltFirmwaresSources) {
    const std::filesystem::path src = RCSIM_COMM_FW_SOURCES;
    const auto d = read_c_declarations({(src / "fw.h").string(), (src / "main.c").string(), (src / "hw.c").string()});
    // main.c: `unsigned rx_len[NO_PORT]` (fw.h NO_PORT 3), `static unsigned char mbq[MBQ]` (MBQ 16).
    EXPECT_EQ(d.at("rx_len").size(), 6u);
    EXPECT_EQ(d.at("mbq").size(), 16u);
    EXPECT_EQ(d.at("tick_div").base, "unsigned int");
}

Symbol data(const std::string& name, std::uint32_t size) {
    Symbol s;
    s.name = name;
    s.size = size;
    s.kind = Symbol::Kind::data;
    return s;
}

TEST(DwarfTypes, DeclarationOrSize) {
    std::map<std::string, CType> decl;
    decl["rx_len"] = CType{"unsigned int", 2, false, false, {3}};
    EXPECT_EQ(variable_type(data("rx_len", 6), decl).dims, std::vector<std::uint32_t>{3});
    // The map leaves padding after a variable: a larger symbol keeps its declaration.
    EXPECT_EQ(variable_type(data("rx_len", 8), decl).size(), 6u);
    // A declaration larger than the map's symbol is of something else: the size decides.
    EXPECT_EQ(variable_type(data("rx_len", 4), decl).size(), 4u);
    EXPECT_EQ(variable_type(data("byte", 1), decl).base, "unsigned char");
    EXPECT_EQ(variable_type(data("word", 2), decl).base, "unsigned int");
    const CType block = variable_type(data("block", 5), decl);
    EXPECT_EQ(block.base, "unsigned char");
    EXPECT_EQ(block.dims, std::vector<std::uint32_t>{5});
    EXPECT_TRUE(variable_type(data("label", 0), decl).base.empty());
}

} // namespace
} // namespace rcsim::debug
