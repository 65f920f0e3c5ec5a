// rcsim — a ROM image as a firmware team has it: a raw image of the whole ROM or of one smaller
// EPROM, an Intel HEX file, or an even/odd pair of 8-bit EPROMs (docs/tools.md "ROM images").
//
// The format is told from the content, never from the file name:
//   - Intel HEX: text whose first non-blank character is ':'. Records 00 (data), 01 (end of
//     file), 02 (extended segment address: base = value x 16), 04 (extended linear address: base
//     = value << 16); 03 and 05 (start address) are accepted and ignored, since the 8086 starts
//     at FFFF:0000 whatever the file says. The first data record decides how addresses read: at
//     or above the ROM's base they are the CPU's (a locator's output, F0000..FFFFF), below it they
//     are offsets into the ROM (an EPROM programmer's view, 0000..FFFF). Bytes no record writes
//     read 0xFF, as an erased EPROM does;
//   - Motorola S-records: text whose first non-blank characters are S0..S9. S1/S2/S3 data at
//     16-, 24- and 32-bit addresses, placed as Intel HEX's are; S0 ignored, S5/S6 checked
//     against the data records before them, S7/S8/S9 end the file (their start address ignored).
//     A text format may start with a UTF-8 byte order mark (skipped); a NUL or another binary
//     byte in it is refused naming its line and column;
//   - a raw image of 8, 16, 32 or 64 KB (for one EPROM of a pair: 4 .. 32 KB). A smaller image is
//     mirrored across the ROM window, as a board that decodes only the address lines the chip
//     has does (a 27256's 32 KB appear at F0000 and at F8000; the reset vector at FFFF0 reads the
//     image's last 16 bytes but for the mirror);
//   - anything else is refused, naming the file and what was found: an ELF file or a DOS .EXE
//     (with the command that converts it), text that is not Intel HEX or S-records, another size.
//
// An even/odd pair is two 8-bit EPROMs on the 16-bit bus: the even one on D0-D7 holds the bytes at
// even addresses, the odd one on D8-D15 those at odd addresses. Each is read as above (raw, Intel
// HEX or S-records, device offsets) for half the window, and they are interleaved; two raw images
// must be of one size (a 32 KB and a 16 KB one would be mirrored differently).
//
// Plain C++ (no SystemC): bad input throws ConfigError naming the file and the line or offset.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rcsim {

/// Where a ROM image comes from: one file, or an even/odd EPROM pair (`odd` not empty).
struct RomSource {
    std::string file; // the whole image, or the even EPROM of a pair
    std::string odd;  // the odd EPROM; empty: `file` is the whole image
};

struct RomImage {
    std::vector<std::uint8_t> bytes; // exactly the window's size
    std::string format;              // what was read, for the report: "raw 32 KB, mirrored 2x", ...
};

/// Reads `src` for a ROM of `window` bytes (a power of two, at least 8 KB) whose first byte the
/// CPU sees at linear address `base`. Throws ConfigError.
RomImage read_rom_image(const RomSource& src, std::uint32_t base, std::size_t window);

/// The bytes of an Intel HEX text placed in a window of `window` bytes at CPU address `base`
/// (`base` 0: device offsets only); `written`, when given, counts the bytes the records wrote.
/// `file` names the text in errors. Throws ConfigError naming the line.
std::vector<std::uint8_t> parse_intel_hex(const std::string& text, const std::string& file, std::uint32_t base,
                                          std::size_t window, std::size_t* written = nullptr);

/// The same for Motorola S-records (S19, S28, S37): S1/S2/S3 data records at 16-, 24- and 32-bit
/// addresses, S0 (header) and S7/S8/S9 (start address) ignored, S5/S6 (record count) checked.
std::vector<std::uint8_t> parse_srecord(const std::string& text, const std::string& file, std::uint32_t base,
                                        std::size_t window, std::size_t* written = nullptr);

} // namespace rcsim
