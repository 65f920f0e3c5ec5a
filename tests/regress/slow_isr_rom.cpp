// slow_isr_rom — a deliberately slowed firmware: the built ROM with a delay loop spliced into the
// common RS-232 interrupt entry (comm_cpu/firmware/frozen_all_c/crt0.s `rs232_entry`, in the
// frozen C firmware comm_fw_c.rom, which every 82510 interrupt that reaches the C handler passes).
// Used by the regression tests and the worked example of docs/regression.md to show that
// `rcsim compare` catches a slower ISR.
//
//   slow_isr_rom IN.rom SYMBOLS.json OUT.rom LOOPS
//
// crt0.s: `_isr_port2: push ax; mov ax,#2` falls through into `rs232_entry: push bx; push cx;
// push dx; ...`, i.e. the bytes 50 B8 02 00 | 53 51 52. The three one-byte pushes become a near
// JMP (E9 rel16, three bytes) to a trampoline in the unused tail of the ROM (0xFF padding below
// the reset stub at FFF0):
//     push bx; push cx; push dx      ; what the JMP replaced
//     mov cx, LOOPS
//     loop $                         ; LOOPS-1 taken (17 clocks each), one not taken (5)
//     jmp rs232_entry+3
// CX is saved by then and scratch to the C handler, LOOP leaves the flags alone: the firmware does
// the same work, only later. Refuses a ROM whose bytes differ from the above.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

constexpr std::size_t kTrampoline = 0xFF00; // inside the 0xFF padding, below the reset stub at 0xFFF0

int fail(const std::string& why) {
    std::fprintf(stderr, "slow_isr_rom: %s\n", why.c_str());
    return 2;
}

void put_rel16(std::vector<std::uint8_t>& rom, std::size_t at, std::size_t from_next, std::size_t to) {
    const auto rel = static_cast<std::uint16_t>(to - from_next);
    rom[at] = static_cast<std::uint8_t>(rel & 0xFF);
    rom[at + 1] = static_cast<std::uint8_t>(rel >> 8);
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 5) return fail("usage: slow_isr_rom IN.rom SYMBOLS.json OUT.rom LOOPS");
    std::ifstream in(argv[1], std::ios::binary);
    std::vector<std::uint8_t> rom((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
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
    if (!sym.contains("symbols") || !sym["symbols"].contains("isr_port2"))
        return fail(std::string(argv[2]) + ": no symbol isr_port2");
    const std::size_t port2 = sym["symbols"]["isr_port2"]["offset"].get<std::size_t>();
    const std::uint8_t expect[] = {0x50, 0xB8, 0x02, 0x00, 0x53, 0x51, 0x52};
    for (std::size_t i = 0; i < sizeof expect; ++i)
        if (port2 + i >= rom.size() || rom[port2 + i] != expect[i])
            return fail("the bytes at isr_port2 are not push ax; mov ax,#2; push bx; push cx; push dx");
    for (std::size_t i = kTrampoline; i < kTrampoline + 16; ++i)
        if (rom[i] != 0xFF) return fail("ROM offset FF00 is not free (0xFF padding)");
    const std::size_t entry = port2 + 4; // rs232_entry
    rom[entry] = 0xE9;                   // jmp near trampoline
    put_rel16(rom, entry + 1, entry + 3, kTrampoline);
    std::size_t t = kTrampoline;
    for (std::uint8_t b : {0x53, 0x51, 0x52}) rom[t++] = b;               // push bx; push cx; push dx
    rom[t++] = 0xB9;                                                      // mov cx, imm16
    rom[t++] = static_cast<std::uint8_t>(loops & 0xFF);
    rom[t++] = static_cast<std::uint8_t>(loops >> 8);
    rom[t++] = 0xE2;                                                      // loop $
    rom[t++] = 0xFE;
    rom[t++] = 0xE9;                                                      // jmp near rs232_entry+3
    put_rel16(rom, t, t + 2, entry + 3);
    std::ofstream out(argv[3], std::ios::binary);
    out.write(reinterpret_cast<const char*>(rom.data()), static_cast<std::streamsize>(rom.size()));
    if (!out) return fail(std::string(argv[3]) + ": cannot write");
    return 0;
}
