// Tests of the frame encoder/decoder and the escape syntax.
#include "models/frame_codec.h"

#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>

using namespace rcsim;
using namespace rcsim::proto;

namespace {
std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
}
} // namespace

TEST(FrameCodec, EncodesWithTheChecksumOfT1ThroughTheLastDataByte) {
    // E+C+STX+0+0+h+e+l+l+o = 0x2FE: checksum "FE".
    EXPECT_EQ(encode(Frame{"EC", 0, "hello"}), std::string("\x01" "EC\x02" "00helloFE\x03"));
    EXPECT_EQ(encode(Frame{"ST", 0x0A, ""}), std::string("\x01" "ST\x02" "0A") + hex2(sum8("ST\x02" "0A")) + "\x03");
    EXPECT_EQ(hex2(0x5c), "5C");
}

TEST(FrameCodec, RoundTripsUpToTheLengthLimit) {
    for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{339}, max_data}) {
        Frame f{"PU", 0x03, std::string(n, 'x')};
        Frame g;
        EXPECT_EQ(decode(encode(f), g), "");
        EXPECT_EQ(g, f);
    }
}

TEST(FrameCodec, EncodeRejectsBadFramesNamingTheValue) {
    EXPECT_NE(error_of([] { encode(Frame{"E", 0, ""}); }).find("token 'E'"), std::string::npos);
    EXPECT_NE(error_of([] { encode(Frame{"E\x01", 0, ""}); }).find("\\x01"), std::string::npos);
    EXPECT_NE(error_of([] { encode(Frame{"EC", 0, "ab\x03"}); }).find("offset 2"), std::string::npos);
    EXPECT_NE(error_of([] { encode(Frame{"EC", 0, std::string(max_data + 1, 'a')}); }).find("8193"),
              std::string::npos);
}

TEST(FrameCodec, DecoderFindsEveryFault) {
    Frame f;
    const std::string good = encode(Frame{"EC", 0, "hello"});
    std::string bad_sum = good;
    bad_sum[good.size() - 2] = '0';
    EXPECT_NE(decode(bad_sum, f).find("checksum F0, expected FE"), std::string::npos); 
    std::string lower = good;
    lower[good.size() - 2] = 'e';
    EXPECT_NE(decode(lower, f).find("not two uppercase hex"), std::string::npos);
    std::string no_stx = good;
    no_stx[3] = '+';
    EXPECT_NE(decode(no_stx, f).find("not STX"), std::string::npos);
    std::string ctrl = good;
    ctrl[7] = '\x07';
    EXPECT_NE(decode(ctrl, f).find("printable"), std::string::npos);
    EXPECT_NE(decode(std::string("\x01" "EC\x03"), f).find("too short"), std::string::npos);
    EXPECT_NE(decode(std::string("\x01" "EC\x02" "ZZ") + hex2(sum8("EC\x02ZZ")) + "\x03", f).find("BCH"),
              std::string::npos);
    const std::string longer = std::string("\x01" "EC\x02" "00") + std::string(max_data + 1, 'a') + "00\x03";
    EXPECT_NE(decode(longer, f).find("longer than 8192"), std::string::npos);

    FrameDecoder d;
    for (std::size_t i = 0; i + 1 < good.size(); ++i)
        EXPECT_EQ(d.feed(static_cast<std::uint8_t>(good[i]), i == 6), FrameDecoder::Result::more);
    EXPECT_EQ(d.feed(ETX), FrameDecoder::Result::bad);
    EXPECT_NE(d.error().find("byte 6 arrived with a parity or framing error"), std::string::npos);
}

TEST(FrameCodec, EscapesAndUnescapes) {
    EXPECT_EQ(unescape("\\x05A\\ACK\\n\\\\\\0"), std::string("\x05" "A\x06\n\\") + std::string(1, '\0'));
    EXPECT_EQ(unescape("\\SOHEC\\STX"), "\x01" "EC\x02");
    EXPECT_EQ(escape(std::string("\x05" "ab\\\x7f")), "\\x05ab\\\\\\x7F");
    EXPECT_EQ(unescape(escape("\x01\x02\x03 hi\\")), "\x01\x02\x03 hi\\");
    EXPECT_NE(error_of([] { unescape("ab\\xZ1"); }).find("'\\xZ1' at offset 2"), std::string::npos);
    EXPECT_NE(error_of([] { unescape("\\q"); }).find("'\\q' at offset 0"), std::string::npos);
    EXPECT_NE(error_of([] { unescape("x\\"); }).find("offset 1"), std::string::npos);
    EXPECT_NE(error_of([] { unescape("\\x4"); }).find("'\\x4'"), std::string::npos);
}

namespace {
std::string raw_bytes(std::initializer_list<int> v) {
    std::string s;
    for (int c : v) s += char(c);
    return s;
}
} // namespace

// Whole-frame decode (what the main CPU does with a reassembled frame).
TEST(FrameCodecWhole, EncodesTheDocumentedLayoutWithChecksumFromT1ThroughData) {
    // Sum of 'E' 'C' STX '0' '0' 'h' 'i' = 0x45+0x43+0x02+0x30+0x30+0x68+0x69 = 0x1BB -> BB.
    const std::string wire = proto::encode({"EC", 0x00, "hi"});
    EXPECT_EQ(wire, raw_bytes({0x01, 'E', 'C', 0x02, '0', '0', 'h', 'i', 'B', 'B', 0x03}));
}

TEST(FrameCodecWhole, DecodesWhatItEncodes) {
    proto::Frame f;
    ASSERT_EQ(proto::decode(proto::encode({"PW", 0x2A, "12,-7"}), f), "");
    EXPECT_EQ(f.token, "PW");
    EXPECT_EQ(f.bch, 0x2A);
    EXPECT_EQ(f.data, "12,-7");
}

TEST(FrameCodecWhole, AcceptsEmptyAndMaximumData) {
    proto::Frame f;
    EXPECT_EQ(proto::decode(proto::encode({"ST", 0, ""}), f), "");
    EXPECT_EQ(f.data, "");
    const std::string big(proto::max_data, 'x');
    EXPECT_EQ(proto::decode(proto::encode({"EC", 0, big}), f), "");
    EXPECT_EQ(f.data.size(), 8192u);
}

TEST(FrameCodecWhole, RejectsBadChecksumNamingBothValues) {
    std::string wire = proto::encode({"EC", 0, "hi"});
    wire[8] = '0'; // BB -> 0B
    proto::Frame f;
    const std::string why = proto::decode(wire, f);
    EXPECT_NE(why.find("0B"), std::string::npos) << why;
    EXPECT_NE(why.find("BB"), std::string::npos) << why;
}

TEST(FrameCodecWhole, RejectsStructuralErrors) {
    proto::Frame f;
    const std::string good = proto::encode({"EC", 0, "abc"});
    std::string no_soh = good;
    no_soh[0] = 'X';
    EXPECT_NE(proto::decode(no_soh, f).find("SOH"), std::string::npos);
    std::string no_stx = good;
    no_stx[3] = 'X';
    EXPECT_NE(proto::decode(no_stx, f).find("STX"), std::string::npos);
    EXPECT_NE(proto::decode(good.substr(0, good.size() - 1), f).find("ETX"), std::string::npos);
    EXPECT_NE(proto::decode(good.substr(0, 5), f).find("ETX"), std::string::npos);
    EXPECT_NE(proto::decode(raw_bytes({0x01, 'E', 'C', 0x02, '0', '0', '0', 0x03}), f).find("too short"),
              std::string::npos);
    std::string lower_bch = good;
    lower_bch[4] = 'a';
    EXPECT_NE(proto::decode(lower_bch, f).find("BCH"), std::string::npos);
}

TEST(FrameCodecWhole, RejectsNonPrintableDataNamingTheByte) {
    std::string wire = proto::encode({"EC", 0, "abc"});
    wire[7] = char(0x7F);
    proto::Frame f;
    const std::string why = proto::decode(wire, f);
    EXPECT_NE(why.find("\\x7F"), std::string::npos) << why;
    EXPECT_NE(why.find("byte 7"), std::string::npos) << why;
}

TEST(FrameCodecWhole, RejectsOverlongFrame) {
    proto::Frame f;
    std::string wire = proto::encode({"EC", 0, std::string(proto::max_data, 'x')});
    wire.insert(6, "y");
    EXPECT_NE(proto::decode(wire, f).find("longer than"), std::string::npos);
}

TEST(FrameCodecWhole, EncodeRejectsBadInputWithOneClearError) {
    EXPECT_THROW(proto::encode({"E", 0, ""}), std::invalid_argument);
    EXPECT_THROW(proto::encode({"EC", 0, std::string(8193, 'x')}), std::invalid_argument);
    try {
        proto::encode({"EC", 0, std::string("a\tb")});
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("\\x09"), std::string::npos) << e.what();
    }
}
