#include "models/rom_image.h"

#include "models/plumbing/config_error.h"
#include "models/plumbing/hex.h"

#include <algorithm>
#include <cctype>
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

bool text_byte(std::uint8_t c) { return c == '\t' || c == '\n' || c == '\r' || (c >= 0x20 && c < 0x7F); }

bool looks_like_text(const std::vector<std::uint8_t>& b, std::size_t from = 0) {
    return std::all_of(b.begin() + static_cast<std::ptrdiff_t>(from), b.end(), text_byte);
}

/// Throws, naming the line and column, at the first byte of `b` (from `from`) that is not text:
/// a NUL or another binary byte in a text format.
void not_text_at(const std::vector<std::uint8_t>& b, std::size_t from, const std::string& file, const char* what) {
    int line = 1;
    std::size_t column = 1;
    for (std::size_t i = from; i < b.size(); ++i, ++column) {
        if (b[i] == '\n') line += 1, column = 0;
        if (!text_byte(b[i]))
            throw ConfigError(file, line, "byte " + hex(b[i]) + (b[i] == 0 ? " (NUL)" : "") + " at column " +
                                              std::to_string(column) + ": " + what + " is text");
    }
}

/// Whether `size` is one a raw image may have in `window`: a power of two, window / 8 .. window.
bool raw_size(std::size_t size, std::size_t window) {
    return size != 0 && (size & (size - 1)) == 0 && size >= window / 8 && size <= window;
}

/// Whether the line starting at `from` is a whole record, ':' or "Sn" then hex digits to its end:
/// a raw image whose first bytes happen to be ':' or "S1" is not that.
bool first_line_is_record(std::vector<std::uint8_t>::const_iterator from, std::vector<std::uint8_t>::const_iterator end) {
    auto eol = std::find(from, end, '\n');
    if (eol != from && eol[-1] == '\r') --eol;
    const auto digits = from + (*from == ':' ? 1 : 2);
    return eol - digits >= 8 && std::all_of(digits, eol, [](std::uint8_t c) { return std::isxdigit(c) != 0; });
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
    if (!raw_size(b.size(), window))
        throw ConfigError(file, 0, "ROM image is " + std::to_string(b.size()) + " bytes; a raw image is " + kb(smallest) +
                                       " .. " + kb(window) + " (a power of two; the ROM is " + kb(window) +
                                       ", the reset vector at FFFF:0000 in its last 16 bytes), or give Intel HEX or "
                                       "Motorola S-records (e.g. `objcopy -I binary -O ihex --change-addresses 0xF0000 "
                                       "FILE rom.hex`)");
    if (looks_like_text(b))
        throw ConfigError(file, 1, "text that is not Intel HEX (no ':' record) or S-records (no S0..S9 record), not a "
                                   "ROM image: '" + first_line(b) + "'");
    std::vector<std::uint8_t> out(window);
    for (std::size_t i = 0; i < window; ++i) out[i] = b[i % b.size()];
    format = "raw " + kb(b.size());
    if (b.size() < window) format += ", mirrored " + std::to_string(window / b.size()) + "x across " + kb(window);
    return out;
}

/// One image of `window` bytes from a file of any supported format; `base` 0: device offsets only.
/// `raw`, when given, is set to the raw image's size (0: a text format, placed by its addresses).
std::vector<std::uint8_t> one_image(const std::string& file, std::uint32_t base, std::size_t window, std::string& format,
                                    std::size_t* raw = nullptr) {
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
                                       " bytes; a raw image is at most 64 KB, an Intel HEX or S-record file at most " +
                                       std::to_string(kMaxFile >> 20) + " MB");
    }
    // A text format, by its first record: Intel HEX (':') or Motorola S-records ("S0".."S9"),
    // after a UTF-8 byte order mark if an editor wrote one (it is not part of the text).
    const std::size_t bom = starts_with(b, {0xEF, 0xBB, 0xBF}) ? 3 : 0;
    const auto first = std::find_if(b.begin() + bom, b.end(),
                                    [](std::uint8_t c) { return c != ' ' && c != '\t' && c != '\r' && c != '\n'; });
    const bool intel = first != b.end() && *first == ':';
    const bool motorola = first != b.end() && *first == 'S' && first + 1 != b.end() && first[1] >= '0' && first[1] <= '9';
    // Text, or a record-like start in a file no raw image could be: a damaged text file, whose
    // binary byte not_text_at names (a raw image may start with ':' or "S1" by chance).
    const bool text_format = looks_like_text(b, bom) || !raw_size(b.size(), window) || first_line_is_record(first, b.end());
    if ((intel || motorola) && text_format) {
        not_text_at(b, bom, file, intel ? "Intel HEX" : "an S-record file");
        const std::string text(b.begin() + bom, b.end());
        std::size_t written = 0;
        std::vector<std::uint8_t> out = intel ? parse_intel_hex(text, file, base, window, &written)
                                              : parse_srecord(text, file, base, window, &written);
        format = (intel ? "Intel HEX, " : "Motorola S-records, ") + std::to_string(written) + " bytes";
        return out;
    }
    if (raw) *raw = b.size();
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

/// The window being written by a HEX or S-record file: where each byte goes, and which line wrote
/// it. The first data record decides how addresses read: at or above `base` (not 0) the CPU's,
/// below it offsets into the ROM.
class Placer {
public:
    Placer(const std::string& file, std::uint32_t base, std::size_t window)
        : file_(file), base_(base), window_(window), out_(window, 0xFF), line_of_(window, 0) {}

    void put(std::uint32_t a, std::uint8_t byte, int n) {
        if (!placed_) cpu_addresses_ = base_ != 0 && a >= base_, placed_ = true;
        const std::uint32_t o = cpu_addresses_ ? a - base_ : a;
        if (cpu_addresses_ ? a < base_ || o >= window_ : o >= window_)
            throw ConfigError(file_, n, "address " + hex(a, 5) + " is outside the ROM (" +
                                            (cpu_addresses_ ? hex(base_, 5) + ".." + hex(base_ + window_ - 1, 5)
                                                            : "offsets 0.." + hex(window_ - 1, 4)) + ")");
        if (line_of_[o])
            throw ConfigError(file_, n, "address " + hex(a, 5) + " again: line " + std::to_string(line_of_[o]) +
                                            " wrote it (overlapping records)");
        line_of_[o] = n;
        out_[o] = byte;
        ++count_;
    }
    std::size_t count() const { return count_; }
    std::vector<std::uint8_t> take() { return std::move(out_); }

private:
    const std::string& file_;
    std::uint32_t base_;
    std::size_t window_;
    std::vector<std::uint8_t> out_; // an erased EPROM until written
    std::vector<int> line_of_;      // which line wrote each byte: 0 none
    bool cpu_addresses_ = false, placed_ = false;
    std::size_t count_ = 0;
};

/// Calls `record(line, n)` for each line of `text` that is not blank, without its line end and
/// trailing blanks; returns the number of the last line.
template <typename F> int for_each_line(const std::string& text, F record) {
    int n = 0;
    std::size_t at = 0;
    while (at < text.size()) {
        const std::size_t eol = std::min(text.find('\n', at), text.size());
        std::string line = text.substr(at, eol - at);
        at = eol + 1;
        ++n;
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
        if (!line.empty()) record(line, n);
    }
    return n;
}

} // namespace

std::vector<std::uint8_t> parse_intel_hex(const std::string& text, const std::string& file, std::uint32_t base,
                                          std::size_t window, std::size_t* written) {
    Placer rom(file, base, window);
    std::uint32_t upper = 0; // from the last 02 or 04 record
    bool linear = false;     // ... an 04: 32-bit addresses, no 64 KB wrap
    bool ended = false;
    const int n = for_each_line(text, [&](const std::string& line, int n) {
        if (ended) throw ConfigError(file, n, "a record after the end-of-file record");
        if (line[0] != ':') throw ConfigError(file, n, "not an Intel HEX record (no ':'): '" + line.substr(0, 40) + "'");
        const std::vector<std::uint8_t> r = record_bytes(line, file, n);
        const unsigned length = r[0], offset = static_cast<unsigned>(r[1] << 8 | r[2]), type = r[3];
        const unsigned value = length >= 2 ? static_cast<unsigned>(r[4] << 8 | r[5]) : 0;
        switch (type) {
        case 0x00:
            // After a segment record (02) addresses wrap within their 64 KB segment; after a
            // linear one (04) they are 32-bit and run on past it (the Intel HEX specification).
            for (unsigned i = 0; i < length; ++i)
                rom.put(linear ? upper + offset + i : upper + ((offset + i) & 0xFFFF), r[4 + i], n);
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
    });
    if (!ended) throw ConfigError(file, n, "no end-of-file record (:00000001FF): the file is cut short");
    if (rom.count() == 0) throw ConfigError(file, n, "no data record: nothing to put in the ROM");
    if (written) *written = rom.count();
    return rom.take();
}

// Motorola S-records: "S" TYPE COUNT ADDRESS DATA CHECKSUM, COUNT the bytes after it (address,
// data, checksum), the checksum the ones' complement of the low byte of the sum of the others.
std::vector<std::uint8_t> parse_srecord(const std::string& text, const std::string& file, std::uint32_t base,
                                        std::size_t window, std::size_t* written) {
    Placer rom(file, base, window);
    // The address's bytes by type: S0 header, S1-S3 data, S5/S6 record count, S7-S9 termination.
    static constexpr unsigned kAddressBytes[10] = {2, 2, 3, 4, 0, 2, 3, 4, 3, 2};
    std::size_t data_records = 0;
    bool ended = false;
    const int n = for_each_line(text, [&](const std::string& line, int n) {
        if (ended) throw ConfigError(file, n, "a record after the termination record (S7, S8 or S9)");
        if (line.size() < 2 || line[0] != 'S' || line[1] < '0' || line[1] > '9')
            throw ConfigError(file, n, "not an S-record (S0..S9 then pairs of hex digits): '" + line.substr(0, 40) + "'");
        const unsigned type = static_cast<unsigned>(line[1] - '0');
        if (type == 4) throw ConfigError(file, n, "record type S4 is reserved, not one of S0..S3, S5..S9");
        if (line.size() % 2 != 0)
            throw ConfigError(file, n, "an odd number of hex digits after S" + std::to_string(type) + ": '" +
                                           line.substr(0, 40) + "'");
        std::vector<std::uint8_t> r;
        unsigned sum = 0;
        for (std::size_t i = 2; i < line.size(); i += 2) {
            const unsigned hi = hex_digit(line[i]), lo = hex_digit(line[i + 1]);
            if (hi > 15 || lo > 15) throw ConfigError(file, n, "'" + line.substr(i, 2) + "' is not a hex byte");
            r.push_back(static_cast<std::uint8_t>(hi << 4 | lo));
            sum += r.back();
        }
        const unsigned address_bytes = kAddressBytes[type];
        if (r.empty() || r[0] + 1u != r.size() || r[0] < address_bytes + 1)
            throw ConfigError(file, n, "the record says " + (r.empty() ? std::string("nothing") : std::to_string(r[0])) +
                                           " bytes follow and " + std::to_string(r.empty() ? 0 : r.size() - 1) +
                                           " do (an S" + std::to_string(type) + " record: " +
                                           std::to_string(address_bytes) + " address bytes, data, checksum)");
        if ((sum & 0xFF) != 0xFF) {
            const unsigned want = ~(sum - r.back()) & 0xFF;
            throw ConfigError(file, n, "bad checksum " + hex(r.back()) + ", the record's bytes give " + hex(want));
        }
        std::uint32_t address = 0;
        for (unsigned i = 1; i <= address_bytes; ++i) address = address << 8 | r[i];
        const std::size_t data = 1 + address_bytes, length = r.size() - 1 - data;
        if (type >= 1 && type <= 3) {
            for (std::size_t i = 0; i < length; ++i) rom.put(address + static_cast<std::uint32_t>(i), r[data + i], n);
            ++data_records;
        } else if ((type == 5 || type == 6) && address != data_records) {
            throw ConfigError(file, n, "the record count (S" + std::to_string(type) + ") says " + std::to_string(address) +
                                           " data records and " + std::to_string(data_records) + " came before it");
        } else if (type >= 7) {
            ended = true; // the start address: the 8086 starts at FFFF:0000 whatever the file says
        }
    });
    if (rom.count() == 0) throw ConfigError(file, n, "no data record (S1, S2, S3): nothing to put in the ROM");
    if (written) *written = rom.count();
    return rom.take();
}

RomImage read_rom_image(const RomSource& src, std::uint32_t base, std::size_t window) {
    RomImage img;
    if (src.odd.empty()) {
        img.bytes = one_image(src.file, base, window, img.format);
        return img;
    }
    // Each EPROM of the pair sees half the bytes, at its own offsets.
    std::string even_format, odd_format;
    std::size_t even_size = 0, odd_size = 0;
    const std::vector<std::uint8_t> even = one_image(src.file, 0, window / 2, even_format, &even_size);
    const std::vector<std::uint8_t> odd = one_image(src.odd, 0, window / 2, odd_format, &odd_size);
    // Two raw images of different sizes would be mirrored differently, so that a word would join
    // bytes of different addresses: a pair is two EPROMs of one type (issue #48).
    if (even_size && odd_size && even_size != odd_size)
        throw ConfigError("even/odd EPROM pair of different sizes: " + src.file + " (even) is " + kb(even_size) +
                          ", " + src.odd + " (odd) is " + kb(odd_size) + "; an even/odd pair is two EPROMs of one size");
    img.bytes.resize(window);
    for (std::size_t i = 0; i < window / 2; ++i) {
        img.bytes[2 * i] = even[i];
        img.bytes[2 * i + 1] = odd[i];
    }
    img.format = "even/odd EPROM pair: even " + even_format + ", odd " + odd_format;
    return img;
}

} // namespace rcsim
