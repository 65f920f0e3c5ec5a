// Tests of the main CPU's frame codec (SYSTEM.md §3).
#include "main_cpu/frame.h"

#include <gtest/gtest.h>

using namespace rcsim;

namespace {
std::string bytes(std::initializer_list<int> v) {
    std::string s;
    for (int c : v) s += char(c);
    return s;
}
} // namespace

TEST(Frame, EncodesTheDocumentedLayoutWithChecksumFromT1ThroughData) {
    // Sum of 'E' 'C' STX '0' '0' 'h' 'i' = 0x45+0x43+0x02+0x30+0x30+0x68+0x69 = 0x1BB -> BB.
    const std::string wire = frame::encode({"EC", 0x00, "hi"});
    EXPECT_EQ(wire, bytes({0x01, 'E', 'C', 0x02, '0', '0', 'h', 'i', 'B', 'B', 0x03}));
}

TEST(Frame, DecodesWhatItEncodes) {
    frame::Frame f;
    ASSERT_EQ(frame::decode(frame::encode({"PW", 0x2A, "12,-7"}), f), "");
    EXPECT_EQ(f.token, "PW");
    EXPECT_EQ(f.bch, 0x2A);
    EXPECT_EQ(f.data, "12,-7");
}

TEST(Frame, AcceptsEmptyAndMaximumData) {
    frame::Frame f;
    EXPECT_EQ(frame::decode(frame::encode({"ST", 0, ""}), f), "");
    EXPECT_EQ(f.data, "");
    const std::string big(frame::max_data, 'x');
    EXPECT_EQ(frame::decode(frame::encode({"EC", 0, big}), f), "");
    EXPECT_EQ(f.data.size(), 8192u);
}

TEST(Frame, RejectsBadChecksumNamingBothValues) {
    std::string wire = frame::encode({"EC", 0, "hi"});
    wire[8] = '0'; // BB -> 0B
    frame::Frame f;
    const std::string why = frame::decode(wire, f);
    EXPECT_NE(why.find("0B"), std::string::npos) << why;
    EXPECT_NE(why.find("BB"), std::string::npos) << why;
}

TEST(Frame, RejectsStructuralErrors) {
    frame::Frame f;
    const std::string good = frame::encode({"EC", 0, "abc"});
    std::string no_soh = good;
    no_soh[0] = 'X';
    EXPECT_NE(frame::decode(no_soh, f).find("SOH"), std::string::npos);
    std::string no_stx = good;
    no_stx[3] = 'X';
    EXPECT_NE(frame::decode(no_stx, f).find("STX"), std::string::npos);
    EXPECT_NE(frame::decode(good.substr(0, good.size() - 1), f).find("ETX"), std::string::npos);
    EXPECT_NE(frame::decode(good.substr(0, 5), f).find("shorter"), std::string::npos);
    EXPECT_NE(frame::decode(bytes({0x01, 'E', 'C', 0x02, '0', '0', '0', 0x03}), f).find("9-byte"),
              std::string::npos);
    std::string lower_bch = good;
    lower_bch[4] = 'a';
    EXPECT_NE(frame::decode(lower_bch, f).find("BCH"), std::string::npos);
}

TEST(Frame, RejectsNonPrintableDataNamingTheByte) {
    std::string wire = frame::encode({"EC", 0, "abc"});
    wire[7] = char(0x7F);
    frame::Frame f;
    const std::string why = frame::decode(wire, f);
    EXPECT_NE(why.find("0x7F"), std::string::npos) << why;
    EXPECT_NE(why.find("data byte 1"), std::string::npos) << why;
}

TEST(Frame, RejectsOverlongFrame) {
    frame::Frame f;
    std::string wire = frame::encode({"EC", 0, std::string(frame::max_data, 'x')});
    wire.insert(6, "y");
    EXPECT_NE(frame::decode(wire, f).find("over the limit"), std::string::npos);
}

TEST(Frame, EncodeRejectsBadInputWithOneClearError) {
    EXPECT_THROW(frame::encode({"E", 0, ""}), std::invalid_argument);
    EXPECT_THROW(frame::encode({"EC", 0, std::string(8193, 'x')}), std::invalid_argument);
    try {
        frame::encode({"EC", 0, std::string("a\tb")});
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("0x09"), std::string::npos) << e.what();
    }
}
