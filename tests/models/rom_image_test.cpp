// ROM images as firmware teams have them (models/rom_image.h): raw images mirrored as partial
// address decoding does, Intel HEX placed by its records' addresses (the record layout and the
// checksum of the Intel HEX specification), and even/odd EPROM pairs interleaved byte by byte.
#include "models/plumbing/config_error.h"
#include "models/rom_image.h"
#include "tests/support/files.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace rcsim;
namespace fs = std::filesystem;

namespace {

constexpr std::uint32_t kBase = 0xF0000;
constexpr std::size_t kWindow = 0x10000;

std::string file_with(const std::string& name, const std::string& bytes) {
    const fs::path p = rcsim::test::scratch_dir() / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p.string();
}

/// Bytes 0..n-1 that are not text: i * 7 + 0x80, wrapping.
std::string binary(std::size_t n) {
    std::string s(n, '\0');
    for (std::size_t i = 0; i < n; ++i) s[i] = static_cast<char>(i * 7 + 0x80);
    return s;
}

/// One Intel HEX record: ':', length, address, type, data, and the checksum, the two's complement
/// of the sum of the bytes before it (the specification's rule).
std::string record(unsigned type, unsigned address, const std::vector<unsigned>& data) {
    std::vector<unsigned> b = {static_cast<unsigned>(data.size()), address >> 8 & 0xFF, address & 0xFF, type};
    b.insert(b.end(), data.begin(), data.end());
    unsigned sum = 0;
    for (unsigned x : b) sum += x;
    b.push_back((0x100 - (sum & 0xFF)) & 0xFF);
    std::string s = ":";
    char hex[3];
    for (unsigned x : b) std::snprintf(hex, sizeof hex, "%02X", x), s += hex;
    return s + "\n";
}

const std::string kEof = ":00000001FF\n"; // the specification's end-of-file record

/// The message parse_intel_hex throws for `text` read as `file` ("(no error)" if it takes it).
std::string hex_error(const std::string& text, const std::string& file) {
    try {
        parse_intel_hex(text, file, kBase, kWindow);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "(no error)";
}

std::string error_of(const RomSource& src) {
    try {
        read_rom_image(src, kBase, kWindow);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "(no error)";
}

/// One Motorola S-record: "S" TYPE, the count of the bytes after it, the address in `address_bytes`
/// bytes, the data and the checksum, the ones' complement of the low byte of the sum of the count,
/// address and data bytes (the format's definition, as srec_cat writes it).
std::string srecord(unsigned type, unsigned address_bytes, std::uint32_t address, const std::vector<unsigned>& data) {
    std::vector<unsigned> b = {static_cast<unsigned>(address_bytes + data.size() + 1)};
    for (unsigned i = address_bytes; i-- > 0;) b.push_back(address >> (8 * i) & 0xFF);
    b.insert(b.end(), data.begin(), data.end());
    unsigned sum = 0;
    for (unsigned x : b) sum += x;
    b.push_back(~sum & 0xFF);
    std::string s = "S" + std::to_string(type);
    char hex[3];
    for (unsigned x : b) std::snprintf(hex, sizeof hex, "%02X", x), s += hex;
    return s + "\n";
}

std::string srec_error(const std::string& text, const std::string& file) {
    try {
        parse_srecord(text, file, kBase, kWindow);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "(no error)";
}

} // namespace

TEST(RomImage, ARaw64KbImageIsTheRom) {
    const std::string b = binary(kWindow);
    const RomImage img = read_rom_image({file_with("64k.bin", b), {}}, kBase, kWindow);
    EXPECT_EQ(std::string(img.bytes.begin(), img.bytes.end()), b);
    EXPECT_EQ(img.format, "raw 64 KB");
}

TEST(RomImage, ASmallerImageIsMirroredAcrossTheWindow) {
    const std::string b = binary(0x2000); // one 2764
    const RomImage img = read_rom_image({file_with("8k.bin", b), {}}, kBase, kWindow);
    EXPECT_EQ(img.format, "raw 8 KB, mirrored 8x across 64 KB");
    for (std::size_t a : {0x0000u, 0x1FFFu, 0x2000u, 0x8123u, 0xFFF0u})
        EXPECT_EQ(img.bytes[a], static_cast<std::uint8_t>(b[a % 0x2000])) << a;
}

TEST(RomImage, OtherSizesTextElfAndExeAreRefusedSayingWhatTheyAre) {
    EXPECT_NE(error_of({file_with("12k.bin", binary(0x3000)), {}}).find("ROM image is 12288 bytes; a raw image is 8 KB .. 64 KB"),
              std::string::npos);
    EXPECT_NE(error_of({file_with("128k.bin", binary(0x20000)), {}}).find("131072 bytes"), std::string::npos);
    EXPECT_NE(error_of({file_with("text.bin", std::string(kWindow, 'A')), {}}).find("text that is not Intel HEX"),
              std::string::npos);
    EXPECT_NE(error_of({file_with("a.elf", "\x7F" "ELF" + binary(100)), {}}).find("objcopy -O binary FILE rom.bin"),
              std::string::npos);
    EXPECT_NE(error_of({file_with("a.exe", "MZ" + binary(100)), {}}).find("a DOS .EXE"), std::string::npos);
    EXPECT_NE(error_of({rcsim::test::scratch_dir().string(), {}}).find("is a directory"), std::string::npos);
}

// The specification's example data record (its checksum A7, computed by hand in the document).
TEST(IntelHex, TheSpecificationsExampleRecordIsPlacedByItsAddress) {
    const std::string text = ":0B0010006164647265737320676170A7\n" + kEof;
    std::size_t written = 0;
    const std::vector<std::uint8_t> rom = parse_intel_hex(text, "spec.hex", kBase, kWindow, &written);
    EXPECT_EQ(written, 11u);
    EXPECT_EQ(std::string(rom.begin() + 0x10, rom.begin() + 0x1B), "address gap");
    EXPECT_EQ(rom[0x0F], 0xFF); // unwritten: erased
    EXPECT_EQ(rom[0x1B], 0xFF);
}

TEST(IntelHex, SegmentAndLinearAddressRecordsGiveCpuAddresses) {
    // 02: segment F000 -> base F0000; 04: upper 000F -> base F0000. Both put the byte at FFFF0.
    for (const std::string& upper : {record(0x02, 0, {0xF0, 0x00}), record(0x04, 0, {0x00, 0x0F})}) {
        const std::string text = upper + record(0x00, 0xFFF0, {0xEA, 0x00, 0x00, 0x00, 0xF0}) + kEof;
        const std::vector<std::uint8_t> rom = parse_intel_hex(text, "cpu.hex", kBase, kWindow);
        EXPECT_EQ(rom[0xFFF0], 0xEA);
        EXPECT_EQ(rom[0xFFF4], 0xF0);
        EXPECT_EQ(rom[0x0000], 0xFF);
    }
}

// The specification: after an extended linear address record (04) a data record's addresses are
// 32-bit, ULBA x 65536 + offset + i, and do not wrap at its 64 KB; after an extended segment
// address record (02) they wrap within the segment. A linear record running past FFFFF leaves the
// ROM (issue #48: it was wrapped to F0000, and overwrote it when that was free).
TEST(IntelHex, LinearAddressesRunPastTheir64KbAndSegmentAddressesWrap) {
    auto error = [](const std::string& text) { return hex_error(text, "l.hex"); };
    EXPECT_EQ(error(record(0x04, 0, {0x00, 0x0F}) + record(0, 0xFFFE, {1, 2, 3, 4}) + kEof),
              "l.hex:2: address 100000 is outside the ROM (F0000..FFFFF)");
    EXPECT_EQ(error(record(0x04, 0, {0x00, 0x0F}) + record(0, 0x0000, {9}) + record(0, 0xFFFF, {1, 2}) + kEof),
              "l.hex:3: address 100000 is outside the ROM (F0000..FFFFF)");
    // The same bytes after a segment record F000: FFFF then 0000 of the segment, F0000.
    const std::vector<std::uint8_t> rom =
        parse_intel_hex(record(0x02, 0, {0xF0, 0x00}) + record(0, 0xFFFF, {1, 2}) + kEof, "s.hex", kBase, kWindow);
    EXPECT_EQ(rom[0xFFFF], 1);
    EXPECT_EQ(rom[0x0000], 2);
}

TEST(IntelHex, BadRecordsAreRefusedNamingTheLine) {
    auto error = [](const std::string& text) { return hex_error(text, "x.hex"); };
    EXPECT_EQ(error(":0B0010006164647265737320676170A8\n" + kEof), "x.hex:1: bad checksum A8, the record's bytes give A7");
    EXPECT_EQ(error(record(0, 0x100, {1, 2}) + record(0, 0x101, {3}) + kEof),
              "x.hex:2: address 00101 again: line 1 wrote it (overlapping records)");
    EXPECT_EQ(error(record(0x04, 0, {0x00, 0x0E}) + record(0, 0x0000, {1}) + kEof),
              "x.hex:2: address E0000 is outside the ROM (offsets 0..FFFF)");
    EXPECT_EQ(error(record(0x02, 0, {0xF0, 0x00}) + record(0, 0x10, {1}) + record(0x02, 0, {0xE0, 0x00}) +
                    record(0, 0x10, {1}) + kEof),
              "x.hex:4: address E0010 is outside the ROM (F0000..FFFFF)");
    EXPECT_EQ(error(record(0, 0, {1})), "x.hex:1: no end-of-file record (:00000001FF): the file is cut short");
    EXPECT_EQ(error(kEof + record(0, 0, {1})), "x.hex:2: a record after the end-of-file record");
    EXPECT_EQ(error(record(0x06, 0, {}) + kEof), "x.hex:1: record type 06 is not one of Intel HEX's 00..05");
    EXPECT_EQ(error(":0100000G01\n" + kEof), "x.hex:1: '0G' is not a hex byte");
    EXPECT_EQ(error(":02000000FF\n" + kEof), "x.hex:1: the record says 2 data bytes and has 0");
    EXPECT_EQ(error(kEof), "x.hex:1: no data record: nothing to put in the ROM");
}

TEST(RomImage, AnEvenOddPairIsInterleavedAsTheBusWiresIt) {
    const std::string even = binary(0x8000), odd = std::string(0x8000, '\xA5');
    const RomImage img = read_rom_image({file_with("even.bin", even), file_with("odd.bin", odd)}, kBase, kWindow);
    EXPECT_EQ(img.format, "even/odd EPROM pair: even raw 32 KB, odd raw 32 KB");
    for (std::size_t i : {0u, 1u, 0x4000u, 0x7FFFu}) {
        EXPECT_EQ(img.bytes[2 * i], static_cast<std::uint8_t>(even[i])) << i;
        EXPECT_EQ(img.bytes[2 * i + 1], 0xA5) << i;
    }
}

TEST(RomImage, APairOfSmallerEpromsIsMirroredEachWithinItsHalf) {
    const std::string even = binary(0x2000), odd = binary(0x2000);
    const RomImage img = read_rom_image({file_with("e8.bin", even), file_with("o8.bin", odd)}, kBase, kWindow);
    // Byte address 2i comes from even[i mod 8K]: F0000 + 0xFFF0 reads even[0x7FF8 mod 0x2000].
    EXPECT_EQ(img.bytes[0xFFF0], static_cast<std::uint8_t>(even[0x7FF8 % 0x2000]));
    EXPECT_EQ(img.bytes[0xFFF1], static_cast<std::uint8_t>(odd[0x7FF8 % 0x2000]));
}

// Issue #48: pairs of EPROMs of different sizes were mirrored each in its own way, silently.
TEST(RomImage, APairOfDifferentSizesIsRefusedNamingBothFilesAndSizes) {
    const std::string e32 = file_with("e32.bin", binary(0x8000)), o16 = file_with("o16.bin", binary(0x4000)),
                      o8 = file_with("o8.bin", binary(0x2000));
    EXPECT_EQ(error_of({e32, o16}), "even/odd EPROM pair of different sizes: " + e32 + " (even) is 32 KB, " + o16 +
                                        " (odd) is 16 KB; an even/odd pair is two EPROMs of one size");
    EXPECT_EQ(error_of({o8, e32}), "even/odd EPROM pair of different sizes: " + o8 + " (even) is 8 KB, " + e32 +
                                       " (odd) is 32 KB; an even/odd pair is two EPROMs of one size");
}

// Issue #48: a HEX file with a byte order mark or a NUL was "a raw image of the wrong size". The
// mark an editor writes is not part of the text and is skipped; a NUL is named where it is.
TEST(IntelHex, AByteOrderMarkIsSkippedAndANulIsNamedByLineAndColumn) {
    const std::string text = record(0x00, 0x0010, {0xAB}) + kEof;
    const RomImage img = read_rom_image({file_with("bom.hex", "\xEF\xBB\xBF" + text), {}}, kBase, kWindow);
    EXPECT_EQ(img.format, "Intel HEX, 1 bytes");
    EXPECT_EQ(img.bytes[0x10], 0xAB);
    const std::string nul = file_with("nul.hex", text + std::string(":0000\0", 6) + "0001FF\n");
    EXPECT_EQ(error_of({nul, {}}), nul + ":3: byte 00 (NUL) at column 6: Intel HEX is text");
    const std::string first = file_with("nul1.hex", ":1000\x01" + text);
    EXPECT_EQ(error_of({first, {}}), first + ":1: byte 01 at column 6: Intel HEX is text");
    // A raw image of a raw size whose first byte happens to be ':' is still a raw image.
    std::string raw = binary(0x2000);
    raw[0] = ':';
    EXPECT_EQ(read_rom_image({file_with("colon.bin", raw), {}}, kBase, kWindow).format, "raw 8 KB, mirrored 8x across 64 KB");
}

// S-records as srec_cat writes them (S0 header, S1/S2/S3 data, S5 count, S7/S8/S9 optional).
TEST(SRecord, S19S28AndS37ArePlacedByTheirAddresses) {
    const std::string s0 = srecord(0, 2, 0, {'r', 'c'}), s5 = srecord(5, 2, 1, {});
    // S1: 16-bit device offsets; S2 and S3: the CPU's F0000..FFFFF.
    for (const std::string& text : {s0 + srecord(1, 2, 0xFFF0, {0xEA, 0x00}) + s5 + srecord(9, 2, 0, {}),
                                    s0 + srecord(2, 3, 0xFFFF0, {0xEA, 0x00}) + s5 + srecord(8, 3, 0xFFFF0, {}),
                                    s0 + srecord(3, 4, 0xFFFF0, {0xEA, 0x00}) + s5 + srecord(7, 4, 0xFFFF0, {}),
                                    srecord(3, 4, 0xFFFF0, {0xEA, 0x00})}) {
        std::size_t written = 0;
        const std::vector<std::uint8_t> rom = parse_srecord(text, "s.srec", kBase, kWindow, &written);
        EXPECT_EQ(written, 2u) << text;
        EXPECT_EQ(rom[0xFFF0], 0xEA) << text;
        EXPECT_EQ(rom[0xFFF1], 0x00) << text;
        EXPECT_EQ(rom[0xFFEF], 0xFF) << text; // unwritten: erased
    }
    const RomImage img = read_rom_image({file_with("fw.s19", s0 + srecord(1, 2, 0x10, {1, 2, 3}) + s5), {}}, kBase, kWindow);
    EXPECT_EQ(img.format, "Motorola S-records, 3 bytes");
    EXPECT_EQ(img.bytes[0x12], 3);
}

TEST(SRecord, BadRecordsAreRefusedNamingTheLineAsIntelHexOnesAre) {
    auto error = [](const std::string& text) { return srec_error(text, "x.s19"); };
    // Checksum: count 04, address 0010, data 01 sum to 15, its complement EA.
    EXPECT_EQ(error("S104001001EA\n"), "(no error)");
    EXPECT_EQ(error("S104001001EC\n"), "x.s19:1: bad checksum EC, the record's bytes give EA");
    EXPECT_EQ(error("S105001001EA\n"),
              "x.s19:1: the record says 5 bytes follow and 4 do (an S1 record: 2 address bytes, data, checksum)");
    EXPECT_EQ(error("S10400100GEA\n"), "x.s19:1: '0G' is not a hex byte");
    EXPECT_EQ(error("S104001001E\n"), "x.s19:1: an odd number of hex digits after S1: 'S104001001E'");
    EXPECT_EQ(error("X104001001EA\n"), "x.s19:1: not an S-record (S0..S9 then pairs of hex digits): 'X104001001EA'");
    EXPECT_EQ(error(srecord(4, 2, 0, {1})), "x.s19:1: record type S4 is reserved, not one of S0..S3, S5..S9");
    EXPECT_EQ(error(srecord(1, 2, 0x100, {1, 2}) + srecord(1, 2, 0x101, {3})),
              "x.s19:2: address 00101 again: line 1 wrote it (overlapping records)");
    EXPECT_EQ(error(srecord(2, 3, 0xE0000, {1})), "x.s19:1: address E0000 is outside the ROM (offsets 0..FFFF)");
    EXPECT_EQ(error(srecord(2, 3, 0xF0000, {1}) + srecord(2, 3, 0xFFFFF, {1, 2})),
              "x.s19:2: address 100000 is outside the ROM (F0000..FFFFF)");
    EXPECT_EQ(error(srecord(1, 2, 0, {1}) + srecord(1, 2, 1, {1}) + srecord(5, 2, 3, {})),
              "x.s19:3: the record count (S5) says 3 data records and 2 came before it");
    EXPECT_EQ(error(srecord(1, 2, 0, {1}) + srecord(9, 2, 0, {}) + srecord(1, 2, 1, {1})),
              "x.s19:3: a record after the termination record (S7, S8 or S9)");
    EXPECT_EQ(error(srecord(0, 2, 0, {'x'}) + srecord(5, 2, 0, {})),
              "x.s19:2: no data record (S1, S2, S3): nothing to put in the ROM");
}
