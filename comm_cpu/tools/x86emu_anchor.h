// rcsim — the libx86emu reference run of `rcsim bench cpu --anchor`: the same 8086 image on an
// instruction-level emulator (libx86emu, not cycle-exact), so the core's speed is a ratio
// measured side by side in one run rather than a figure that moves with the host's load.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rcsim::anchor {

/// What both emulators must agree on after a run of the bench image (docs/performance.md).
struct Outcome {
    std::uint64_t instructions = 0; // as the emulator counts them (a REP run is one)
    std::uint16_t ax = 0, bx = 0, bp = 0, ip = 0;
    std::uint32_t out_sum = 0;      // sum of the bytes written to the RESULT port
    std::uint32_t status_reads = 0; // IN from the STATUS port
    double cpu_seconds = 0;         // host CPU time of the run, for the report only
    bool operator==(const Outcome& o) const {
        return instructions == o.instructions && ax == o.ax && bx == o.bx && bp == o.bp && ip == o.ip &&
               out_sum == o.out_sum && status_reads == o.status_reads;
    }
};

/// The bench ports, shared by both runs: STATUS (80h) reads 01h every 4th time, DATA (82h) the
/// low byte of the STATUS read count, RESULT (84h) is summed.
struct LoopPorts {
    static constexpr std::uint16_t kStatus = 0x80, kData = 0x82, kResult = 0x84;
    std::uint32_t status_reads = 0, out_sum = 0;
    std::uint8_t in(std::uint16_t port) {
        if (port == kStatus) return (++status_reads % 4 == 0) ? 0x01 : 0x00;
        if (port == kData) return std::uint8_t(status_reads);
        return 0xFF;
    }
    void out(std::uint16_t port, std::uint8_t v) {
        if (port == kResult) out_sum += v;
    }
};

/// Load segment of the image (both runs start at 1000:0000 with a 1 MB RAM).
constexpr std::uint32_t kLoadSegment = 0x1000;

/// The bytes of an image file (std::runtime_error naming the file when it cannot be read).
std::vector<std::uint8_t> read_image(const std::string& path);
/// Runs `image` on libx86emu from 1000:0000 until HLT.
Outcome run_x86emu(const std::vector<std::uint8_t>& image);
/// Runs `image` on the rcsim core (trace off) from 1000:0000 until HLT.
Outcome run_core(const std::vector<std::uint8_t>& image);

} // namespace rcsim::anchor
