// slow_isr_rom — a deliberately slowed firmware: a built ROM with a delay loop spliced into the
// entry of its RS-232 interrupts. Used by the regression tests and the worked example of
// docs/regression.md to show that `rcsim compare` catches a slower ISR.
//
//   slow_isr_rom IN.rom SYMBOLS.json OUT.rom LOOPS
//
// It knows the two firmwares the build makes, told apart by the bytes at their entries:
//
// - the shipped firmware (comm_fw.rom, comm_cpu/firmware/isr.s): each port has its own entry,
//   `_isr_portN: push ax; in al,GIR_N` (50 E4 nn). Those three bytes become a near JMP (E9
//   rel16) to the port's own trampoline, which does them after the loop:
//       push ax; push cx; mov cx,LOOPS; loop $; pop cx; in al,GIR_N; jmp _isr_portN+3
// - the frozen C firmware (comm_fw_c.rom, frozen_all_c/crt0.s): `_isr_port2: push ax; mov ax,#2`
//   falls through into the common `rs232_entry: push bx; push cx; push dx` (50 B8 02 00 | 53 51
//   52), which every port's interrupt passes. The three pushes become the JMP, to
//       push bx; push cx; push dx; mov cx,LOOPS; loop $; jmp rs232_entry+3
//
// The trampolines go in the unused tail of the ROM (0xFF padding below the reset stub at FFF0).
// LOOP runs LOOPS-1 times taken (17 clocks each) and once not (5); CX is saved around it (or
// scratch by then) and LOOP leaves the flags alone: the firmware does the same work, only later.
// A ROM whose bytes are neither is refused (exit 2).
#include "tests/support/files.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <vector>

namespace {

using Rom = std::vector<std::uint8_t>;

constexpr std::size_t kTrampolines = 0xFF00; // inside the 0xFF padding, below the reset stub at 0xFFF0
constexpr std::size_t kTrampolineSize = 16;

int fail(const std::string& why) {
    std::fprintf(stderr, "slow_isr_rom: %s\n", why.c_str());
    return 2;
}

bool bytes_at(const Rom& rom, std::size_t at, std::initializer_list<std::uint8_t> want) {
    for (std::uint8_t b : want)
        if (at >= rom.size() || rom[at++] != b) return false;
    return true;
}

void put_rel16(Rom& rom, std::size_t at, std::size_t from_next, std::size_t to) {
    const auto rel = static_cast<std::uint16_t>(to - from_next);
    rom[at] = static_cast<std::uint8_t>(rel & 0xFF);
    rom[at + 1] = static_cast<std::uint8_t>(rel >> 8);
}

/// Replaces the three bytes at `entry` with a JMP to a trampoline at `t`: `before`, the loop,
/// `after`, then a JMP back to entry+3.
void splice(Rom& rom, std::size_t entry, std::size_t t, std::initializer_list<std::uint8_t> before, long loops,
            std::initializer_list<std::uint8_t> after) {
    rom[entry] = 0xE9; // jmp near trampoline
    put_rel16(rom, entry + 1, entry + 3, t);
    for (std::uint8_t b : before) rom[t++] = b;
    rom[t++] = 0xB9; // mov cx, imm16
    rom[t++] = static_cast<std::uint8_t>(loops & 0xFF);
    rom[t++] = static_cast<std::uint8_t>(loops >> 8);
    rom[t++] = 0xE2; // loop $
    rom[t++] = 0xFE;
    for (std::uint8_t b : after) rom[t++] = b;
    rom[t++] = 0xE9; // jmp near entry+3
    put_rel16(rom, t, t + 2, entry + 3);
}

std::size_t offset_of(const nlohmann::json& sym, const std::string& name) {
    return sym["symbols"][name]["offset"].get<std::size_t>();
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 5) return fail("usage: slow_isr_rom IN.rom SYMBOLS.json OUT.rom LOOPS");
    Rom rom = rcsim::test::slurp_bytes(argv[1]);
    if (rom.size() != 0x10000) return fail(std::string(argv[1]) + ": not a 64 KB ROM image");
    nlohmann::json sym;
    try {
        std::ifstream js(argv[2]);
        sym = nlohmann::json::parse(js);
    } catch (const std::exception& e) {
        return fail(std::string(argv[2]) + ": " + e.what());
    }
    const long loops = std::strtol(argv[4], nullptr, 10);
    if (loops < 1 || loops > 0xFFFF) return fail("LOOPS must be 1 .. 65535");
    for (const char* name : {"isr_port0", "isr_port1", "isr_port2"})
        if (!sym.contains("symbols") || !sym["symbols"].contains(name) || !sym["symbols"][name].contains("offset"))
            return fail(std::string(argv[2]) + ": no symbol " + name);
    for (std::size_t i = kTrampolines; i < kTrampolines + 3 * kTrampolineSize; ++i)
        if (rom[i] != 0xFF) return fail("ROM offsets FF00..FF2F are not free (0xFF padding)");

    const std::size_t port2 = offset_of(sym, "isr_port2");
    if (bytes_at(rom, port2, {0x50, 0xB8, 0x02, 0x00, 0x53, 0x51, 0x52})) {
        // The frozen C firmware: one common entry, rs232_entry = _isr_port2 + 4.
        splice(rom, port2 + 4, kTrampolines, {0x53, 0x51, 0x52}, loops, {});
    } else {
        // The shipped firmware: one entry per port, `push ax; in al,GIR`.
        std::size_t t = kTrampolines;
        for (const char* name : {"isr_port0", "isr_port1", "isr_port2"}) {
            const std::size_t entry = offset_of(sym, name);
            if (entry + 3 > rom.size() || rom[entry] != 0x50 || rom[entry + 1] != 0xE4)
                return fail(std::string("the bytes at ") + name +
                            " are not push ax; in al,GIR (the shipped firmware) nor, at isr_port2, "
                            "push ax; mov ax,#2; push bx; push cx; push dx (the frozen C firmware)");
            const std::uint8_t gir = rom[entry + 2];
            splice(rom, entry, t, {0x50, 0x51}, loops, {0x59, 0xE4, gir}); // push ax; push cx | pop cx; in al,GIR
            t += kTrampolineSize;
        }
    }
    std::ofstream out(argv[3], std::ios::binary);
    out.write(reinterpret_cast<const char*>(rom.data()), static_cast<std::streamsize>(rom.size()));
    if (!out) return fail(std::string(argv[3]) + ": cannot write");
    return 0;
}
