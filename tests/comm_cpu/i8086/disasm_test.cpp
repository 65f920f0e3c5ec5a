// The instruction decoder (comm_cpu/i8086/disasm.h): every instruction of the hardware-captured
// SingleStepTests vectors decodes to the length of the bytes the capture lists for it (prefixes
// included), and its flow and mnemonic agree with the instruction the vector names. Encodings
// below come from the iAPX 86/88 User's Manual's instruction tables.
#include "comm_cpu/i8086/disasm.h"
#include "comm_cpu/i8086/sst.h"
#include "tests/support/sc_test.h"

#include <nlohmann/json.hpp>

#include <vector>

using rcsim::i8086::decode;
using rcsim::i8086::Flow;
using rcsim::i8086::mnemonic;

namespace {

rcsim::i8086::Decoded decoded(std::vector<std::uint8_t> b) { return decode(b.data(), static_cast<unsigned>(b.size())); }
unsigned length(std::vector<std::uint8_t> b) { return decoded(std::move(b)).length; }

} // namespace

TEST(Disasm, LengthsOfTheEncodingForms) {
    EXPECT_EQ(length({0x90}), 1u);                              // NOP
    EXPECT_EQ(length({0x04, 0x12}), 2u);                        // ADD AL, imm8
    EXPECT_EQ(length({0x05, 0x34, 0x12}), 3u);                  // ADD AX, imm16
    EXPECT_EQ(length({0x01, 0xC0}), 2u);                        // ADD AX, AX: mod 11
    EXPECT_EQ(length({0x01, 0x06, 0x34, 0x12}), 4u);            // ADD [1234h], AX: mod 00 r/m 110
    EXPECT_EQ(length({0x01, 0x47, 0x05}), 3u);                  // ADD [BX+5], AX: mod 01
    EXPECT_EQ(length({0x01, 0x87, 0x00, 0x10}), 4u);            // ADD [BX+1000h], AX: mod 10
    EXPECT_EQ(length({0x81, 0x87, 0x00, 0x10, 0x34, 0x12}), 6u); // the longest form
    EXPECT_EQ(length({0xF6, 0xC0, 0x01}), 3u);                  // TEST AL, 1 (F6 /0 has an immediate)
    EXPECT_EQ(length({0xF6, 0xE0}), 2u);                        // MUL AL (F6 /4 has none)
    EXPECT_EQ(length({0xF7, 0xC8, 0x01, 0x00}), 4u);            // TEST alias F7 /1, word immediate
    EXPECT_EQ(length({0x9A, 0, 0, 0, 0}), 5u);                  // CALL far
    EXPECT_EQ(length({0x2E, 0xF3, 0xA4}), 3u);                  // CS: REP MOVSB
}

TEST(Disasm, BytesThatEndInsideTheInstructionGiveNoLength) {
    EXPECT_EQ(length({0x81, 0x87, 0x00, 0x10, 0x34}), 0u);
    EXPECT_EQ(length({0xFF}), 0u);
    EXPECT_EQ(length({0x26, 0x2E}), 0u);
    EXPECT_EQ(decoded({0x26, 0x2E}).prefixes, 2u);
}

TEST(Disasm, FlowOfControlTransfers) {
    EXPECT_EQ(decoded({0xE8, 0, 0}).flow, Flow::call_near);
    EXPECT_EQ(decoded({0xFF, 0xD0}).flow, Flow::call_near); // FF /2
    EXPECT_EQ(decoded({0xFF, 0x1E, 0, 0}).flow, Flow::call_far); // FF /3
    EXPECT_EQ(decoded({0xFF, 0xE0}).flow, Flow::jump);      // FF /4
    EXPECT_EQ(decoded({0xFF, 0x2E, 0, 0}).flow, Flow::jump_far); // FF /5
    EXPECT_EQ(decoded({0xFF, 0xF0}).flow, Flow::next);      // FF /6 PUSH
    EXPECT_EQ(decoded({0x74, 0x00}).flow, Flow::branch);
    EXPECT_EQ(decoded({0x64, 0x00}).flow, Flow::branch);    // the 8086 runs 64 as 74
    EXPECT_EQ(decoded({0xE2, 0xFE}).flow, Flow::branch);    // LOOP
    EXPECT_EQ(decoded({0xC3}).flow, Flow::ret_near);
    EXPECT_EQ(decoded({0xC1}).flow, Flow::ret_near);        // alias of C3
    EXPECT_EQ(decoded({0xC9}).flow, Flow::ret_far);         // alias of CB
    EXPECT_EQ(decoded({0xCF}).flow, Flow::iret);
    EXPECT_EQ(decoded({0xCD, 0x21}).flow, Flow::int_sw);
    EXPECT_EQ(decoded({0xF4}).flow, Flow::halt);
    EXPECT_EQ(decoded({0xF3, 0xE8, 0, 0}).flow, Flow::call_near); // prefixes are skipped
}

TEST(Disasm, Mnemonics) {
    const auto m = [](std::vector<std::uint8_t> b) { return mnemonic(b.data(), static_cast<unsigned>(b.size())); };
    EXPECT_EQ(m({0xF3, 0xA4}), "REP MOVSB");
    EXPECT_EQ(m({0xF3, 0xA6}), "REPE CMPSB");
    EXPECT_EQ(m({0xF2, 0xAE}), "REPNE SCASB");
    EXPECT_EQ(m({0x2E, 0x8B, 0x07}), "CS: MOV");
    EXPECT_EQ(m({0xF0, 0x87, 0x07}), "LOCK XCHG");
    EXPECT_EQ(m({0xCD, 0x21}), "INT 21h");
    EXPECT_EQ(m({0x80, 0x3E, 0, 0, 1}), "CMP"); // 80 /7
    EXPECT_EQ(m({0xD1, 0xE0}), "SHL");
    EXPECT_EQ(m({0xD6}), "opcode D6h");
    EXPECT_EQ(m({0x26}), "ES: ?");
}

// Each vector's "bytes" are the instruction as the capture fetched it (upstream README); the
// name's first word is its mnemonic ("call", "callf", "retn", "retf" for the transfers).
TEST(Disasm, EveryVectorDecodesToTheLengthOfItsBytes) {
    const std::string dir = rcsim::test::sst_dir();
    if (dir.empty()) GTEST_SKIP() << "SingleStepTests 8086 vectors not present (set RCSIM_SST_DIR)";
    std::size_t files = 0, tests = 0, calls = 0, returns = 0;
    for (const std::string& path : rcsim::i8086::sst::collect({dir})) {
        const nlohmann::json all = nlohmann::json::parse(rcsim::i8086::sst::read_text(path));
        ++files;
        for (const nlohmann::json& t : all) {
            std::vector<std::uint8_t> b = t.at("bytes").get<std::vector<std::uint8_t>>();
            const std::size_t n = b.size();
            b.resize(n + 8, 0x90); // what follows in the capture's queue: NOPs
            const rcsim::i8086::Decoded d = decode(b.data(), static_cast<unsigned>(b.size()));
            ++tests;
            ASSERT_EQ(d.length, n) << path << ": " << t.at("name").get<std::string>();
            const std::string name = t.at("name").get<std::string>();
            const std::string op = name.substr(0, name.find(' '));
            if (op == "call" || op == "callf") {
                ++calls;
                EXPECT_EQ(d.flow, op == "call" ? Flow::call_near : Flow::call_far) << path << ": " << name;
            }
            if (op == "retn" || op == "retf") {
                ++returns;
                EXPECT_EQ(d.flow, op == "retn" ? Flow::ret_near : Flow::ret_far) << path << ": " << name;
            }
        }
    }
    EXPECT_EQ(files, 321u);   // every file of the set but metadata.json
    EXPECT_GT(calls, 0u);     // E8, 9A, FF /2, FF /3 were among them
    EXPECT_GT(returns, 0u);   // C0-C3, C8-CB
    EXPECT_GT(tests, 30000u);
}

TEST(Disasm, DirectTargetsOfEachEncoding) {
    using rcsim::i8086::direct_target;
    auto target = [](std::vector<std::uint8_t> b, std::uint16_t ip) {
        return direct_target(b.data(), decode(b.data(), static_cast<unsigned>(b.size())), ip);
    };
    // rel8 from the end of the instruction: EB FE is a jump to itself.
    EXPECT_EQ(target({0xEB, 0xFE}, 0x100)->ip, 0x100);
    EXPECT_EQ(target({0x74, 0x10}, 0x100)->ip, 0x112);              // JZ +16
    EXPECT_EQ(target({0x64, 0x10}, 0x100)->ip, 0x112);              // its alias 64h
    EXPECT_EQ(target({0xE2, 0x80}, 0x100)->ip, 0x100 + 2 - 128);    // LOOP -128
    EXPECT_EQ(target({0xE9, 0x00, 0x80}, 0xFFF0)->ip, 0x7FF3);      // rel16 wraps in the segment
    EXPECT_EQ(target({0x2E, 0xE8, 0x01, 0x00}, 0x10)->ip, 0x15);    // a prefix counts in the length
    const auto far = target({0xEA, 0x34, 0x12, 0x00, 0xF0}, 0);     // JMP F000:1234
    ASSERT_TRUE(far && far->far);
    EXPECT_EQ(far->cs, 0xF000);
    EXPECT_EQ(far->ip, 0x1234);
    EXPECT_FALSE(target({0xFF, 0xE0}, 0));                          // JMP AX: through a register
    EXPECT_FALSE(target({0xC3}, 0));
    EXPECT_FALSE(target({0x90}, 0));
    EXPECT_FALSE(target({0xE9, 0x00}, 0));                          // the bytes end inside it
}

TEST(Disasm, EveryDirectTransferOfTheVectorsGoesWhereItsTargetSays) {
    // Hardware-captured: a JMP/CALL goes to its target; a conditional branch either there or to
    // the next instruction.
    const std::string dir = rcsim::test::sst_dir();
    if (dir.empty()) GTEST_SKIP() << "SingleStepTests 8086 vectors not present (set RCSIM_SST_DIR)";
    std::size_t checked = 0, taken = 0;
    for (const std::string& path : rcsim::i8086::sst::collect({dir})) {
        const nlohmann::json all = nlohmann::json::parse(rcsim::i8086::sst::read_text(path));
        for (const nlohmann::json& t : all) {
            std::vector<std::uint8_t> b = t.at("bytes").get<std::vector<std::uint8_t>>();
            b.resize(b.size() + 8, 0x90);
            const rcsim::i8086::Decoded d = decode(b.data(), static_cast<unsigned>(b.size()));
            const nlohmann::json& in = t.at("initial").at("regs");
            const nlohmann::json& out = t.at("final").at("regs");
            const auto ip = in.at("ip").get<std::uint16_t>();
            const auto target = rcsim::i8086::direct_target(b.data(), d, ip);
            if (!target) continue;
            ++checked;
            const std::string name = t.at("name").get<std::string>();
            const auto final_ip = out.contains("ip") ? out.at("ip").get<std::uint16_t>() : ip;
            const auto final_cs = out.contains("cs") ? out.at("cs").get<std::uint16_t>() : in.at("cs").get<std::uint16_t>();
            if (d.flow == Flow::branch) {
                const bool went = final_ip == target->ip;
                taken += went ? 1 : 0;
                EXPECT_TRUE(went || final_ip == static_cast<std::uint16_t>(ip + d.length)) << path << ": " << name;
                continue;
            }
            EXPECT_EQ(final_ip, target->ip) << path << ": " << name;
            if (target->far) {
                EXPECT_EQ(final_cs, target->cs) << path << ": " << name;
            }
        }
    }
    EXPECT_GT(checked, 3000u); // EB, E9, E8, EA, 9A, 70-7F, 60-6F, E0-E3: 100 vectors each
    EXPECT_GT(taken, 500u);
}
