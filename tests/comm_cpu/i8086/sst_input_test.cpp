// The SingleStepTests reader: bad input gives one clear error naming the file; a real vector
// file (when the shared folder is present) runs at level 1.
#include "comm_cpu/i8086/sst.h"
#include "tests/support/sc_test.h"
#include "tests/support/files.h"

#include <zlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

using namespace rcsim::i8086::sst;

namespace {

std::string write_file(const std::string& name, const std::string& text) {
    const auto p = rcsim::test::scratch_dir() / name;
    std::ofstream(p) << text;
    return p.string();
}

const char* kGood = R"([{"name":"nop","bytes":[144],"initial":{"regs":{"ax":0,"bx":0,"cx":0,"dx":0,"cs":4096,
 "ss":0,"ds":0,"es":0,"sp":256,"bp":0,"si":0,"di":0,"ip":0,"flags":61442},"ram":[[65536,144]],"queue":[144]},
 "final":{"regs":{"ip":1},"ram":[[65536,144]],"queue":[]},"idx":0}])";

std::string expect_error(const std::string& path) {
    Runner r;
    try {
        r.run_file(path, Metadata{});
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no error for " << path;
    return "";
}

} // namespace

TEST(SstInput, GoodFileRuns) {
    Runner r;
    const FileResult res = r.run_file(write_file("rcsim_sst_good.json", kGood), Metadata{});
    EXPECT_EQ(res.tests, 1u);
    EXPECT_EQ(res.pass[1], 1u);
}

TEST(SstInput, MalformedJsonNamesTheFile) {
    const std::string p = write_file("rcsim_sst_bad.json", "[{\"name\": ");
    const std::string msg = expect_error(p);
    EXPECT_NE(msg.find(p), std::string::npos) << msg;
    EXPECT_NE(msg.find("malformed"), std::string::npos) << msg;
}

TEST(SstInput, UnknownFieldIsNamed) {
    std::string text = kGood;
    text.replace(text.find("\"idx\""), 5, "\"bogus\"");
    const std::string p = write_file("rcsim_sst_unknown.json", text);
    const std::string msg = expect_error(p);
    EXPECT_NE(msg.find("bogus"), std::string::npos) << msg;
    EXPECT_NE(msg.find(p), std::string::npos) << msg;
}

TEST(SstInput, MissingRegisterAndBadValue) {
    std::string t1 = kGood;
    t1.replace(t1.find("\"bp\":0,"), 7, "");
    EXPECT_NE(expect_error(write_file("rcsim_sst_noreg.json", t1)).find("missing register"), std::string::npos);
    std::string t2 = kGood;
    t2.replace(t2.find("\"ax\":0"), 6, "\"ax\":70000");
    EXPECT_NE(expect_error(write_file("rcsim_sst_range.json", t2)).find("70000"), std::string::npos);
}

TEST(SstInput, TruncatedGzipNamesTheFile) {
    const auto p = (rcsim::test::scratch_dir() / "sst_trunc.json.gz").string();
    gzFile f = gzopen(p.c_str(), "wb");
    ASSERT_TRUE(f);
    std::string big;
    for (int i = 0; i < 200; ++i) big += kGood;
    gzwrite(f, big.data(), unsigned(big.size()));
    gzclose(f);
    std::filesystem::resize_file(p, std::filesystem::file_size(p) / 2);
    const std::string msg = expect_error(p);
    EXPECT_NE(msg.find(p), std::string::npos) << msg;
}

TEST(SstInput, MissingFileIsNamed) {
    try {
        collect({"/nonexistent/rcsim_sst"});
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/rcsim_sst"), std::string::npos);
    }
}

// 8F, C6 and C7 come as one file each whose metadata gives a status per ModR/M reg value (only
// /0 is defined): with a status asked for, only the tests whose reg field has it run, found
// past any prefixes, and the stem says which reg values they are.
TEST(SstInput, StatusPerRegValueSelectsTheTests) {
    const std::string dir = (rcsim::test::scratch_dir() / "sst_by_reg").string();
    std::filesystem::create_directories(dir);
    std::ofstream(dir + "/metadata.json")
        << R"({"opcodes":{"8F":{"reg":{"0":{"status":"normal"},"1":{"status":"undefined"},"2":{"status":"undefined"},
              "3":{"status":"undefined"},"4":{"status":"undefined"},"5":{"status":"undefined"},
              "6":{"status":"undefined"},"7":{"status":"undefined"}}}}})";
    auto with_bytes = [](const std::string& bytes) {
        std::string t = std::string(kGood).substr(1); // one test object, without the array's brackets
        t.pop_back();
        return t.replace(t.find("[144],\"initial\""), 5, bytes);
    };
    // POP [BX] (/0), ES: POP [BX] (/0 after a prefix), /1 [BX] (undefined), and a bare 8F.
    std::ofstream(dir + "/8F.json") << "[" << with_bytes("[143,7]") << "," << with_bytes("[38,143,7]") << ","
                                    << with_bytes("[143,15]") << "," << with_bytes("[143]") << "]";
    const Metadata meta = Metadata::load(dir + "/metadata.json");
    const OpcodeInfo info = meta.lookup("8F");
    EXPECT_TRUE(info.by_reg);
    EXPECT_EQ(info.status_of(0), "normal");
    EXPECT_EQ(info.status_of(1), "undefined");
    EXPECT_TRUE(info.has("normal"));
    EXPECT_TRUE(info.has("undefined"));
    EXPECT_FALSE(info.has("alias"));
    EXPECT_TRUE(meta.lookup_file(dir + "/8F.json").by_reg);
    EXPECT_FALSE(meta.lookup_file(dir + "/8E.json.gz").has("normal")); // no entry: status unknown
    Runner r;
    const FileResult normal = r.run_file(dir + "/8F.json", meta, "normal");
    EXPECT_EQ(normal.tests, 2u);
    EXPECT_EQ(normal.stem, "8F/0");
    EXPECT_EQ(normal.status, "normal");
    const FileResult undefined = r.run_file(dir + "/8F.json", meta, "undefined");
    EXPECT_EQ(undefined.tests, 1u);
    EXPECT_EQ(undefined.stem, "8F/1/2/3/4/5/6/7");
    const FileResult all = r.run_file(dir + "/8F.json", meta);
    EXPECT_EQ(all.tests, 4u);
    EXPECT_EQ(all.status, "by reg");
    std::filesystem::remove_all(dir);
}

TEST(SstInput, SharedVectorsPassLevel1) {
    const std::string dir = rcsim::test::sst_dir();
    if (dir.empty()) GTEST_SKIP() << "SingleStepTests 8086 vectors not present (set RCSIM_SST_DIR)";
    const Metadata meta = Metadata::load(dir + "/metadata.json");
    Runner r;
    const FileResult res = r.run_file(dir + "/00.json.gz", meta);
    EXPECT_EQ(res.status, "normal");
    EXPECT_EQ(res.pass[1], res.tests) << res.first_failure[1];
}
