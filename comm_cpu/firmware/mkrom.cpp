// rcsim — comm_fw_mkrom: turns the ld86 output of the communication firmware into the 64 KB
// ROM image for F0000-FFFFF, and writes its symbol table as JSON and as a C++ header.
//
//   comm_fw_mkrom IMAGE MAP ROM JSON HEADER
//
// IMAGE is `ld86 -0 -d -i -T 0 -D 0` output: the code (linked at offset 0 of CS = F000), then
// the initialised-data image at paragraph __segoff. MAP is the `ld86 -M` listing. The ROM is
// IMAGE at offset 0, 0xFF elsewhere, and at offset FFF0 (physical FFFF0, the reset vector
// FFFF:0000) a far jump to F000:start. The tool checks that the data image sits where the
// start-up code copies it from, that code + data fit below the reset stub, and that the
// variables leave room for the stack below STACK_TOP.
#include "models/plumbing/hex.h"

#include <cstdint>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

constexpr std::uint32_t rom_base = 0xF0000;
constexpr std::uint32_t rom_size = 0x10000;
constexpr std::uint16_t code_seg = 0xF000;
constexpr std::uint16_t data_seg = 0x0040;   // fw.h DATA_SEG
constexpr std::uint16_t stack_top = 0x0C00;  // fw.h STACK_TOP
constexpr std::uint16_t min_stack = 0x0400;  // bytes kept free for the stack
constexpr std::uint32_t reset_offset = 0xFFF0;

struct Symbol {
    std::string module;
    std::string name;  // as in the map, with bcc's leading underscore
    int segment = 0;   // 0 text, 3 data/bss
    std::uint32_t value = 0;
    bool global = false;
    bool absolute = false;
};

std::vector<std::uint8_t> read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open " + path);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// ld86 -M lines: "module  name  seg  value  flags" (flags: R/r = relocatable global/local,
// a = absolute, C = common).
std::map<std::string, Symbol> read_map(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot open " + path);
    std::map<std::string, Symbol> out;
    std::string line;
    int lineno = 0;
    while (std::getline(in, line)) {
        ++lineno;
        std::istringstream ss(line);
        Symbol s;
        std::string seg, value, flags;
        if (!(ss >> s.module >> s.name >> seg >> value >> flags)) continue; // "Total memory used"
        if (seg.size() != 1 || seg[0] < '0' || seg[0] > '9') continue;
        s.segment = seg[0] - '0';
        try {
            s.value = static_cast<std::uint32_t>(std::stoul(value, nullptr, 16));
        } catch (const std::exception&) {
            throw std::runtime_error(path + ":" + std::to_string(lineno) + ": bad value '" + value + "'");
        }
        s.global = flags == "R";
        s.absolute = flags == "a";
        out[s.name] = s;
    }
    return out;
}

const Symbol& need(const std::map<std::string, Symbol>& syms, const std::string& name) {
    auto it = syms.find(name);
    if (it == syms.end()) throw std::runtime_error("symbol " + name + " missing from the map");
    return it->second;
}

std::string plain(const std::string& name) { return name[0] == '_' ? name.substr(1) : name; }

void write_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    if (!out || !(out << text)) throw std::runtime_error("cannot write " + path);
}

int run(int argc, char** argv) {
    if (argc != 6) {
        std::cerr << "usage: comm_fw_mkrom IMAGE MAP ROM JSON HEADER\n";
        return 2;
    }
    const std::string image_path = argv[1], map_path = argv[2], rom_path = argv[3],
                      json_path = argv[4], header_path = argv[5];
    const auto image = read_file(image_path);
    const auto syms = read_map(map_path);

    const std::uint32_t start = need(syms, "start").value;
    const std::uint32_t segoff = need(syms, "__segoff").value;
    const std::uint32_t edata = need(syms, "__edata").value;
    const std::uint32_t end = need(syms, "__end").value;
    const std::uint32_t text_end = segoff * 16;

    if (image.size() != text_end + edata)
        throw std::runtime_error("image is " + std::to_string(image.size()) + " bytes, expected code " +
                                 std::to_string(text_end) + " + data " + std::to_string(edata));
    if (image.size() > reset_offset)
        throw std::runtime_error("code + data (" + std::to_string(image.size()) +
                                 " bytes) overlap the reset stub at FFF0");
    if (end + min_stack > stack_top)
        throw std::runtime_error("variables end at DS:0x" + rcsim::hex(end, 4) + ", leaving less than " +
                                 std::to_string(min_stack) + " bytes of stack below 0x" + rcsim::hex(stack_top, 4));

    std::vector<std::uint8_t> rom(rom_size, 0xFF);
    std::copy(image.begin(), image.end(), rom.begin());
    const std::uint8_t stub[5] = {0xEA, std::uint8_t(start & 0xFF), std::uint8_t(start >> 8),
                                  std::uint8_t(code_seg & 0xFF), std::uint8_t(code_seg >> 8)};
    std::copy(std::begin(stub), std::end(stub), rom.begin() + reset_offset);
    {
        std::ofstream out(rom_path, std::ios::binary);
        out.write(reinterpret_cast<const char*>(rom.data()), std::streamsize(rom.size()));
        if (!out) throw std::runtime_error("cannot write " + rom_path);
    }

    // Global symbols only (C functions and variables, the ISR entries); statics stay private.
    std::ostringstream json, code_h, data_h, table;
    json << "{\n  \"rom\": \"" << rom_path << "\",\n  \"rom_base\": " << rom_base
         << ",\n  \"rom_size\": " << rom_size << ",\n  \"code_segment\": " << code_seg
         << ",\n  \"data_segment\": " << data_seg << ",\n  \"code_bytes\": " << text_end
         << ",\n  \"data_bytes\": " << edata << ",\n  \"bss_bytes\": " << (end - edata)
         << ",\n  \"stack_top\": " << stack_top << ",\n  \"reset_vector\": " << (rom_base + reset_offset)
         << ",\n  \"symbols\": {";
    bool first = true;
    for (const auto& [name, s] : syms) {
        if (!s.global || name.rfind("__", 0) == 0) continue;
        const bool code = s.segment == 0;
        const std::uint32_t linear = code ? rom_base + s.value : data_seg * 16u + s.value;
        json << (first ? "\n" : ",\n") << "    \"" << plain(name) << "\": {\"linear\": " << linear
             << ", \"offset\": " << s.value << ", \"kind\": \"" << (code ? "code" : "data") << "\"}";
        first = false;
        (code ? code_h : data_h) << "constexpr std::uint32_t " << plain(name) << " = 0x" << rcsim::hex(linear, 5)
                                 << ";\n";
        table << "    {\"" << plain(name) << "\", 0x" << rcsim::hex(linear, 5) << ", " << (code ? "true" : "false")
              << "},\n";
    }
    json << "\n  }\n}\n";
    write_file(json_path, json.str());

    std::ostringstream h;
    h << "// Generated by comm_fw_mkrom from " << map_path << " -- do not edit.\n"
      << "// Linear (20-bit physical) addresses of the communication firmware's global symbols.\n"
      << "#pragma once\n\n#include <cstdint>\n\nnamespace rcsim::comm_fw {\n\n"
      << "constexpr const char* rom_path = \"" << rom_path << "\";\n"
      << "constexpr std::uint32_t rom_base = 0x" << rcsim::hex(rom_base, 5) << ";\n"
      << "constexpr std::uint32_t rom_size = 0x" << rcsim::hex(rom_size, 5) << ";\n"
      << "constexpr std::uint16_t code_segment = 0x" << rcsim::hex(code_seg, 4) << ";\n"
      << "constexpr std::uint16_t data_segment = 0x" << rcsim::hex(data_seg, 4) << ";\n"
      << "constexpr std::uint32_t code_bytes = " << text_end << ";\n"
      << "constexpr std::uint32_t data_bytes = " << edata << ";\n"
      << "constexpr std::uint32_t bss_bytes = " << (end - edata) << ";\n\n"
      << "/// ROM offset of the initial value of an initialised variable (data::x < data_end).\n"
      << "constexpr std::uint32_t data_end = 0x" << rcsim::hex(data_seg * 16u + edata, 5) << ";\n"
      << "constexpr std::uint32_t rom_offset_of(std::uint32_t data_linear) {\n"
      << "    return code_bytes + (data_linear - data_segment * 16u);\n}\n\n"
      << "/// Functions and ISR entries (CS = code_segment).\nnamespace code {\n" << code_h.str()
      << "} // namespace code\n\n/// Variables (DS = data_segment).\nnamespace data {\n" << data_h.str()
      << "} // namespace data\n\nstruct Symbol {\n    const char* name;\n    std::uint32_t linear;\n"
      << "    bool code;\n};\n\ninline constexpr Symbol symbols[] = {\n" << table.str() << "};\n\n"
      << "} // namespace rcsim::comm_fw\n";
    write_file(header_path, h.str());

    std::cout << "comm_fw: code " << text_end << " B, data " << edata << " B, bss " << (end - edata)
              << " B, ROM " << rom_path << "\n";
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "comm_fw_mkrom: " << e.what() << "\n";
        return 1;
    }
}
