// Tests of the frame encoder/decoder and the escape syntax.
#include "scenarios/host/frame_codec.h"

#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>

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
