// Tests of models/plumbing/hex.h: the expected strings are written by hand, as printf's "%0*X" gives them.
#include "models/plumbing/hex.h"

#include <gtest/gtest.h>

using rcsim::hex;
using rcsim::HexCase;

TEST(Hex, TwoUpperCaseDigitsByDefault) {
    EXPECT_EQ(hex(0xAB), "AB");
    EXPECT_EQ(hex(0x5C), "5C");
    EXPECT_EQ(hex(0xFF, 2), "FF");
}

TEST(Hex, ZeroPadsToTheWidth) {
    EXPECT_EQ(hex(0), "00");
    EXPECT_EQ(hex(0x7), "07");
    EXPECT_EQ(hex(0x3FF, 3), "3FF");
    EXPECT_EQ(hex(0x12, 3), "012");
    EXPECT_EQ(hex(0xABC, 5), "00ABC");
    EXPECT_EQ(hex(0xFFFF0, 5), "FFFF0");
    EXPECT_EQ(hex(0, 4), "0000");
}

TEST(Hex, AValueWiderThanTheWidthKeepsAllItsDigits) {
    EXPECT_EQ(hex(0x1234, 2), "1234");
    EXPECT_EQ(hex(0x400, 3), "400");
    EXPECT_EQ(hex(0x1000, 3), "1000");
    EXPECT_EQ(hex(0xF0000, 4), "F0000");
}

TEST(Hex, WidthZeroOrOneStillShowsZero) {
    EXPECT_EQ(hex(0, 0), "0");
    EXPECT_EQ(hex(0, 1), "0");
    EXPECT_EQ(hex(0xA, 1), "A");
}

TEST(Hex, SixtyFourBitValues) {
    EXPECT_EQ(hex(0xFFFFFFFFu, 8), "FFFFFFFF");
    EXPECT_EQ(hex(0x123456789ABCDEF0ull, 2), "123456789ABCDEF0");
    EXPECT_EQ(hex(0xFFFFFFFFFFFFFFFFull, 20), "0000FFFFFFFFFFFFFFFF");
}

TEST(Hex, LowerCaseOnRequest) {
    EXPECT_EQ(hex(0xAB, 2, HexCase::lower), "ab");
    EXPECT_EQ(hex(0xBEEF, 6, HexCase::lower), "00beef");
    EXPECT_EQ(hex(0xBEEF, 6, HexCase::upper), "00BEEF");
}
