// rcsim — the training run of the core's profile-guided build (comm_cpu/tools/pgo/README.md).
//
// Runs pgo/train.asm on a core built with -fprofile-generate, the way the SystemC module drives
// it: slices of a few hundred clocks whose limit is also the horizon, the idle fast-forward on,
// a bus hook that watches only INTA and memory writes outside interrupts (as the interrupt
// probe does), INTR raised every 1500 clocks and dropped at the second INTA, I/O ports and a
// device window answered by the bus handler (the window with one wait state). Exit 0 when the
// program reached its HLT, 1 if it did not within the bound, 2 on a bad argument or image.
#include "comm_cpu/i8086/cpu.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <vector>

namespace {

using namespace rcsim;
using namespace rcsim::i8086;

constexpr std::uint32_t kWindow = 0x80000; // the device window: memory above it is the handler's
constexpr std::uint16_t kLoadSegment = 0x1000;

struct TrainingBoard : BusHandler {
    Cpu* cpu = nullptr;
    unsigned status_reads = 0, intas = 0;
    std::uint16_t counter = 0;
    unsigned bus_access(Bus kind, std::uint32_t address, std::uint16_t& data, unsigned, cycles_t) override {
        switch (kind) {
        case Bus::io_read:
            data = address == 0x40 ? std::uint16_t(++status_reads % 3 == 0) : counter++;
            return 0;
        case Bus::int_ack:
            data = 0x20;
            if (++intas % 2 == 0) cpu->set_intr(false);
            return 0;
        case Bus::mem_read:
            data = std::uint16_t(address * 7);
            return 1;
        case Bus::mem_write: return 1;
        default: return 0;
        }
    }
};

// Watches every cycle inside an interrupt (from its INTA to the EOI write), else only INTA and
// memory writes: the narrowing and widening the probe does.
struct Watcher {
    Cpu* cpu = nullptr;
    std::uint64_t seen = 0;
    static void hook(void* self, const BusRecord& r) {
        auto* w = static_cast<Watcher*>(self);
        ++w->seen;
        if (r.kind == Bus::int_ack) w->cpu->set_bus_hook_kinds(kAllBusKinds);
        if (r.kind == Bus::io_write && r.address == 0x20)
            w->cpu->set_bus_hook_kinds(bus_kind_bit(Bus::int_ack) | bus_kind_bit(Bus::mem_write));
    }
};

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s TRAIN_IMAGE\n", argv[0]);
        return 2;
    }
    std::ifstream in(argv[1], std::ios::binary);
    const std::vector<std::uint8_t> image((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in || image.empty() || image.size() > 0x10000) {
        std::fprintf(stderr, "%s: not a training image of 1 byte to 64 KB\n", argv[1]);
        return 2;
    }
    std::unique_ptr<std::uint8_t[]> ram(new std::uint8_t[kWindow]());
    std::copy(image.begin(), image.end(), ram.get() + (kLoadSegment << 4));

    Cpu cpu;
    TrainingBoard board;
    Watcher watcher;
    board.cpu = watcher.cpu = &cpu;
    cpu.map_memory(MemRegion{"ram", 0, kWindow, ram.get(), 0, true});
    cpu.set_bus_handler(&board);
    cpu.set_bus_hook(&Watcher::hook, &watcher, bus_kind_bit(Bus::int_ack) | bus_kind_bit(Bus::mem_write));
    cpu.set_fast_forward(true);
    Registers r;
    r.s[CS] = kLoadSegment;
    cpu.load_state(r, nullptr, 0);

    constexpr cycles_t kBound = 400'000'000, kIrqEvery = 1500, kSlice = 800;
    cycles_t next_irq = kIrqEvery;
    while (!cpu.halted() && cpu.cycles() < kBound) {
        if (cpu.cycles() >= next_irq) {
            cpu.set_intr(true);
            next_irq += kIrqEvery;
        }
        const cycles_t limit = std::min(cpu.cycles() + kSlice, next_irq);
        cpu.run_until(limit, false, limit);
    }
    if (!cpu.halted()) {
        std::fprintf(stderr, "%s: no HLT within %llu clocks\n", argv[1], static_cast<unsigned long long>(kBound));
        return 1;
    }
    std::printf("training run: %llu instructions, %llu clocks, %llu bus cycles watched\n",
                static_cast<unsigned long long>(cpu.instructions()), static_cast<unsigned long long>(cpu.cycles()),
                static_cast<unsigned long long>(watcher.seen));
    return 0;
}
