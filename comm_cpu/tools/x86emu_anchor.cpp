// rcsim — both runs of `rcsim bench cpu --anchor`. See x86emu_anchor.h.
#include "comm_cpu/tools/x86emu_anchor.h"

#include "comm_cpu/i8086/cpu.h"

#include <x86emu.h>

#include <cstring>
#include <ctime>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>

namespace rcsim::anchor {
namespace {

constexpr std::uint32_t kMemSize = 1u << 20;

double cpu_now() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
}

std::unique_ptr<std::uint8_t[]> load(const std::vector<std::uint8_t>& image) {
    if (image.size() > 0x10000) throw std::invalid_argument("bench image larger than 64 KB");
    std::unique_ptr<std::uint8_t[]> mem(new std::uint8_t[kMemSize]());
    std::memcpy(mem.get() + (kLoadSegment << 4), image.data(), image.size());
    return mem;
}

// libx86emu has one memory/I/O callback: I/O goes to the bench ports, memory to the library's
// own handler (which reads the pages mapped onto our buffer).
struct X86emuContext {
    LoopPorts ports;
    x86emu_memio_handler_t memory = nullptr;
};
X86emuContext* g_context = nullptr; // libx86emu's callback has no user pointer of its own

unsigned x86emu_io(x86emu_t* emu, u32 addr, u32* val, unsigned type) {
    switch (type & 0xFF00) {
    case X86EMU_MEMIO_I: *val = g_context->ports.in(std::uint16_t(addr)); return 0;
    case X86EMU_MEMIO_O: g_context->ports.out(std::uint16_t(addr), std::uint8_t(*val)); return 0;
    default: return g_context->memory(emu, addr, val, type);
    }
}

// The rcsim core's bus handler: RAM is mapped directly, only I/O arrives here.
struct CoreBoard : i8086::BusHandler {
    LoopPorts ports;
    unsigned bus_access(i8086::Bus kind, std::uint32_t address, std::uint16_t& data, unsigned,
                        i8086::cycles_t) override {
        if (kind == i8086::Bus::io_read) data = ports.in(std::uint16_t(address));
        if (kind == i8086::Bus::io_write) ports.out(std::uint16_t(address), std::uint8_t(data));
        return 0;
    }
};

} // namespace

std::vector<std::uint8_t> read_image(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open the bench image " + path);
    return std::vector<std::uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

Outcome run_x86emu(const std::vector<std::uint8_t>& image) {
    std::unique_ptr<std::uint8_t[]> mem = load(image);
    X86emuContext ctx;
    g_context = &ctx;
    x86emu_t* emu = x86emu_new(X86EMU_PERM_RWX, X86EMU_PERM_RW);
    for (std::uint32_t page = 0; page < kMemSize; page += X86EMU_PAGE_SIZE)
        x86emu_set_page(emu, page, mem.get() + page);
    ctx.memory = x86emu_set_memio_handler(emu, x86emu_io);
    x86emu_set_seg_register(emu, emu->x86.R_CS_SEL, kLoadSegment);
    emu->x86.R_EIP = 0;
    const double t0 = cpu_now();
    x86emu_run(emu, 0); // returns at HLT
    Outcome o;
    o.cpu_seconds = cpu_now() - t0;
    o.instructions = emu->x86.R_TSC; // libx86emu counts one per instruction, HLT included
    o.ax = emu->x86.R_AX;
    o.bx = emu->x86.R_BX;
    o.bp = emu->x86.R_BP;
    o.ip = emu->x86.R_IP;
    o.out_sum = ctx.ports.out_sum;
    o.status_reads = ctx.ports.status_reads;
    x86emu_done(emu);
    g_context = nullptr;
    return o;
}

Outcome run_core(const std::vector<std::uint8_t>& image) {
    std::unique_ptr<std::uint8_t[]> mem = load(image);
    i8086::Cpu cpu;
    CoreBoard board;
    cpu.map_memory(MemRegion{"ram", 0, kMemSize, mem.get(), 0, true});
    cpu.set_bus_handler(&board);
    i8086::Registers r;
    r.s[i8086::CS] = kLoadSegment;
    cpu.load_state(r, nullptr, 0);
    const double t0 = cpu_now();
    while (!cpu.halted()) cpu.run_until(cpu.cycles() + (1u << 30), false);
    Outcome o;
    o.cpu_seconds = cpu_now() - t0;
    o.instructions = cpu.instructions();
    o.ax = cpu.regs().r[i8086::AX];
    o.bx = cpu.regs().r[i8086::BX];
    o.bp = cpu.regs().r[i8086::BP];
    o.ip = cpu.regs().ip;
    o.out_sum = board.ports.out_sum;
    o.status_reads = board.ports.status_reads;
    return o;
}

} // namespace rcsim::anchor
