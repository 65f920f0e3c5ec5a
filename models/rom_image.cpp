#include "models/rom_image.h"

#include "models/plumbing/config_error.h"
#include "models/plumbing/hex.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace rcsim {

namespace {

// More than any ROM image of this board can take, as Intel HEX with one byte per record: a
// bigger file is not one, and is not read whole.
constexpr std::uintmax_t kMaxFile = 4u << 20;

std::vector<std::uint8_t> read_file(const std::string& path) {
    namespace fs = std::filesystem;
    if (path.empty()) throw ConfigError("ROM image '': an empty path (give a file, or leave it out for the built firmware)");
    // What the path is, before reading it: a device (/dev/zero) would be read without end.
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (fs::is_directory(st)) throw ConfigError(path, 0, "is a directory, not a ROM image");
    if (fs::exists(st) && !fs::is_regular_file(st)) throw ConfigError(path, 0, "is not a regular file (a ROM image)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ConfigError(path, 0, "cannot open ROM image");
    // Read at most one byte more than kMaxFile: enough to tell what a bigger file is.
    std::vector<std::uint8_t> bytes;
    char buf[65536];
    while (bytes.size() <= kMaxFile && (in.read(buf, sizeof buf) || in.gcount() > 0))
        bytes.insert(bytes.end(), buf, buf + in.gcount());
    return bytes;
}

bool starts_with(const std::vector<std::uint8_t>& b, std::initializer_list<std::uint8_t> magic) {
    return b.size() >= magic.size() && std::equal(magic.begin(), magic.end(), b.begin());
}

bool looks_like_text(const std::vector<std::uint8_t>& b) {
    return std::all_of(b.begin(), b.end(), [](std::uint8_t c) { return c == '\t' || c == '\n' || c == '\r' || (c >= 0x20 && c < 0x7F); });
}

std::string first_line(const std::vector<std::uint8_t>& b) {
    std::string s;
    for (std::uint8_t c : b) {
        if (c == '\n' || c == '\r' || s.size() == 40) break;
        s += static_cast<char>(c);
    }
    return s;
}

std::string kb(std::size_t bytes) { return std::to_string(bytes / 1024) + " KB"; }

/// A raw image of a power-of-two size from 8 KB (4 KB for one EPROM of a pair) up to `window`,
/// mirrored across the window.
std::vector<std::uint8_t> raw_image(const std::vector<std::uint8_t>& b, const std::string& file, std::size_t window,
                                    std::string& format) {
    const std::size_t smallest = window / 8;
    const bool power_of_two = b.size() != 0 && (b.size() & (b.size() - 1)) == 0;
    if (!power_of_two || b.size() < smallest || b.size() > window)
        throw ConfigError(file, 0, "ROM image is " + std::to_string(b.size()) + " bytes; a raw image is " + kb(smallest) +
                                       " .. " + kb(window) + " (a power of two; the ROM is " + kb(window) +
                                       ", the reset vector at FFFF:0000 in its last 16 bytes), or give Intel HEX "
                                       "(e.g. `objcopy -I binary -O ihex --change-addresses 0xF0000 FILE rom.hex`)");
    if (looks_like_text(b))
        throw ConfigError(file, 1, "text that is not Intel HEX (no ':' record), not a ROM image: '" + first_line(b) + "'");
    std::vector<std::uint8_t> out(window);
    for (std::size_t i = 0; i < window; ++i) out[i] = b[i % b.size()];
    format = "raw " + kb(b.size());
    if (b.size() < window) format += ", mirrored " + std::to_string(window / b.size()) + "x across " + kb(window);
    return out;
}

/// One image of `window` bytes from a file of any supported format; `base` 0: device offsets only.
std::vector<std::uint8_t> one_image(const std::string& file, std::uint32_t base, std::size_t window, std::string& format) {
    const std::vector<std::uint8_t> b = read_file(file);
    // What it is first: an ELF or an .EXE is told by its header whatever its size.
    if (starts_with(b, {0x7F, 'E', 'L', 'F'}))
        throw ConfigError(file, 0, "an ELF file, not a ROM image: take the ROM's bytes out of it with "
                                   "`objcopy -O binary FILE rom.bin` (or `objcopy -O ihex FILE rom.hex`) and give that");
    if (starts_with(b, {'M', 'Z'}))
        throw ConfigError(file, 0, "a DOS .EXE (MZ header), not a ROM image: an .EXE must be located for the ROM first "
                                   "(your locator's Intel HEX or binary output, or `exe2bin`)");
    if (b.size() > kMaxFile) {
        std::error_code ec;
        const std::uintmax_t size = std::filesystem::file_size(file, ec);
        throw ConfigError(file, 0, "ROM image is " + (ec ? "over " + std::to_string(kMaxFile) : std::to_string(size)) +
                                       " bytes; a raw image is at most 64 KB, an Intel HEX file at most " +
                                       std::to_string(kMaxFile >> 20) + " MB");
    }
    const auto first = std::find_if(b.begin(), b.end(), [](std::uint8_t c) { return c != ' ' && c != '\t' && c != '\r' && c != '\n'; });
    if (first != b.end() && *first == ':' && looks_like_text(b)) {
        std::size_t written = 0;
        std::vector<std::uint8_t> out = parse_intel_hex(std::string(b.begin(), b.end()), file, base, window, &written);
        format = "Intel HEX, " + std::to_string(written) + " bytes";
        return out;
    }
    return raw_image(b, file, window, format);
}

unsigned hex_digit(char c) {
    if (c >= '0' && c <= '9') return static_cast<unsigned>(c - '0');
    if (c >= 'A' && c <= 'F') return static_cast<unsigned>(c - 'A' + 10);
    if (c >= 'a' && c <= 'f') return static_cast<unsigned>(c - 'a' + 10);
    return 16;
}

/// The bytes of one record ":LLAAAATT...CC", checked (digits, length, checksum).
std::vector<std::uint8_t> record_bytes(const std::string& line, const std::string& file, int n) {
    if (line.size() < 11 || (line.size() - 1) % 2 != 0)
        throw ConfigError(file, n, "not an Intel HEX record (':' then pairs of hex digits, at least 5 bytes): '" +
                                       line.substr(0, 40) + "'");
    std::vector<std::uint8_t> bytes;
    unsigned sum = 0;
    for (std::size_t i = 1; i < line.size(); i += 2) {
        const unsigned hi = hex_digit(line[i]), lo = hex_digit(line[i + 1]);
        if (hi > 15 || lo > 15) throw ConfigError(file, n, "'" + line.substr(i, 2) + "' is not a hex byte");
        bytes.push_back(static_cast<std::uint8_t>(hi << 4 | lo));
        sum += bytes.back();
    }
    if (bytes[0] + 5u != bytes.size())
        throw ConfigError(file, n, "the record says " + std::to_string(bytes[0]) + " data bytes and has " +
                                       std::to_string(bytes.size() - 5));
    if ((sum & 0xFF) != 0) {
        const unsigned want = (0x100 - ((sum - bytes.back()) & 0xFF)) & 0xFF;
        throw ConfigError(file, n, "bad checksum " + hex(bytes.back()) + ", the record's bytes give " + hex(want));
    }
    return bytes;
}

} // namespace

std::vector<std::uint8_t> parse_intel_hex(const std::string& text, const std::string& file, std::uint32_t base,
                                          std::size_t window, std::size_t* written) {
    std::vector<std::uint8_t> out(window, 0xFF); // an erased EPROM
    std::vector<int> line_of(window, 0);           // which line wrote each byte: 0 none
    std::uint32_t upper = 0;                       // from the last 02 or 04 record
    bool linear = false;                           // ... an 04: 32-bit addresses, no 64 KB wrap
    bool cpu_addresses = false, placed = false, ended = false;
    std::size_t count = 0;
    int n = 0;
    std::size_t at = 0;
    while (at < text.size()) {
        const std::size_t eol = std::min(text.find('\n', at), text.size());
        std::string line = text.substr(at, eol - at);
        at = eol + 1;
        ++n;
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
        if (line.empty()) continue;
        if (ended) throw ConfigError(file, n, "a record after the end-of-file record");
        if (line[0] != ':') throw ConfigError(file, n, "not an Intel HEX record (no ':'): '" + line.substr(0, 40) + "'");
        const std::vector<std::uint8_t> r = record_bytes(line, file, n);
        const unsigned length = r[0], offset = static_cast<unsigned>(r[1] << 8 | r[2]), type = r[3];
        const unsigned value = length >= 2 ? static_cast<unsigned>(r[4] << 8 | r[5]) : 0;
        switch (type) {
        case 0x00:
            if (!placed) cpu_addresses = base != 0 && upper + offset >= base, placed = true;
            for (unsigned i = 0; i < length; ++i) {
                // After a segment record (02) addresses wrap within their 64 KB segment; after a
                // linear one (04) they are 32-bit and run on past it (the Intel HEX specification).
                const std::uint32_t a = linear ? upper + offset + i : upper + ((offset + i) & 0xFFFF);
                const std::uint32_t o = cpu_addresses ? a - base : a;
                if (cpu_addresses ? a < base || o >= window : o >= window)
                    throw ConfigError(file, n, "address " + hex(a, 5) + " is outside the ROM (" +
                                                   (cpu_addresses ? hex(base, 5) + ".." + hex(base + window - 1, 5)
                                                                  : "offsets 0.." + hex(window - 1, 4)) + ")");
                if (line_of[o])
                    throw ConfigError(file, n, "address " + hex(a, 5) + " again: line " + std::to_string(line_of[o]) +
                                                   " wrote it (overlapping records)");
                line_of[o] = n;
                out[o] = r[4 + i];
                ++count;
            }
            break;
        case 0x01: ended = true; break;
        case 0x02:
        case 0x04:
            if (length != 2) throw ConfigError(file, n, "an address record (type " + hex(type) + ") holds 2 bytes");
            upper = type == 0x02 ? value << 4 : value << 16;
            linear = type == 0x04;
            break;
        case 0x03:
        case 0x05: break; // a start address: the 8086 starts at FFFF:0000 whatever the file says
        default: throw ConfigError(file, n, "record type " + hex(type) + " is not one of Intel HEX's 00..05");
        }
    }
    if (!ended) throw ConfigError(file, n, "no end-of-file record (:00000001FF): the file is cut short");
    if (count == 0) throw ConfigError(file, n, "no data record: nothing to put in the ROM");
    if (written) *written = count;
    return out;
}

RomImage read_rom_image(const RomSource& src, std::uint32_t base, std::size_t window) {
    RomImage img;
    if (src.odd.empty()) {
        img.bytes = one_image(src.file, base, window, img.format);
        return img;
    }
    // Each EPROM of the pair sees half the bytes, at its own offsets.
    std::string even_format, odd_format;
    const std::vector<std::uint8_t> even = one_image(src.file, 0, window / 2, even_format);
    const std::vector<std::uint8_t> odd = one_image(src.odd, 0, window / 2, odd_format);
    img.bytes.resize(window);
    for (std::size_t i = 0; i < window / 2; ++i) {
        img.bytes[2 * i] = even[i];
        img.bytes[2 * i + 1] = odd[i];
    }
    img.format = "even/odd EPROM pair: even " + even_format + ", odd " + odd_format;
    return img;
}

} // namespace rcsim
