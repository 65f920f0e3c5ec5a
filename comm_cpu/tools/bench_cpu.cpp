// rcsim — `rcsim bench cpu`: emulated 8086 cycles per host second, trace off, one core.
// (a) the SingleStepTests instruction streams (parsed first, not timed);
// (b) a protocol-like loop: IN, compare, branch, string moves, ISR entry and IRET;
// (c) with --anchor, the core against libx86emu on the same image (protocol_loop.asm),
//     side by side in one run: the ratio of their instruction rates.
// Host time is measured here only, for the report; nothing of it enters the model.
#include "comm_cpu/i8086/cpu.h"
#include "comm_cpu/i8086/sst.h"
#include "comm_cpu/tools/x86emu_anchor.h"
#include "models/plumbing/cli_range.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace rcsim {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A UART-like status port that reports "ready" every 4th read and an INTR raised every
// 2000 cycles (cleared by the INTA), as the firmware's receive path would see.
struct LoopBoard : i8086::BusHandler {
    i8086::Cpu* cpu = nullptr;
    unsigned reads = 0;
    i8086::cycles_t next_irq = 2000;
    unsigned bus_access(i8086::Bus kind, std::uint32_t, std::uint16_t& data, unsigned, i8086::cycles_t start) override {
        if (kind == i8086::Bus::io_read) data = (++reads % 4 == 0) ? 0x01 : 0x00;
        if (kind == i8086::Bus::int_ack) {
            data = 0x20;
            cpu->set_intr(false);
            next_irq = start + 2000;
        }
        return 0;
    }
};

double bench_loop(double min_seconds, std::uint64_t* cycles_out) {
    std::unique_ptr<std::uint8_t[]> ram(new std::uint8_t[1 << 20]);
    std::memset(ram.get(), 0x90, 1 << 20);
    // 1000:0000  STI
    // loop:      IN AL,DX ; TEST AL,1 ; JZ loop ; MOV CX,16 ; REP MOVSW ; SUB SI,32 ; SUB DI,32
    //            CMP AL,1 ; JNE loop ; JMP loop
    const std::uint8_t code[] = {0xFB, 0xEC, 0xA8, 0x01, 0x74, 0xFB, 0xB9, 0x10, 0x00, 0xF3, 0xA5,
                                 0x83, 0xEE, 0x20, 0x83, 0xEF, 0x20, 0x3C, 0x01, 0x75, 0xEE, 0xEB, 0xEC};
    std::memcpy(ram.get() + 0x10000, code, sizeof code);
    ram[0x80] = 0x00; ram[0x81] = 0x05; ram[0x82] = 0; ram[0x83] = 0; // vector 20h -> 0000:0500
    const std::uint8_t isr[] = {0x50, 0x43, 0x58, 0xCF};           // PUSH AX; INC BX; POP AX; IRET
    std::memcpy(ram.get() + 0x500, isr, sizeof isr);
    i8086::Cpu cpu;
    LoopBoard board;
    board.cpu = &cpu;
    cpu.map_memory(MemRegion{"ram", 0, 1u << 20, ram.get(), 0, true});
    cpu.set_bus_handler(&board);
    i8086::Registers r;
    r.s[i8086::CS] = 0x1000;
    r.s[i8086::DS] = 0x2000;
    r.s[i8086::ES] = 0x3000;
    r.s[i8086::SS] = 0x4000;
    r.r[i8086::SP] = 0xFFFE;
    cpu.load_state(r, nullptr, 0);
    const auto t0 = std::chrono::steady_clock::now();
    const i8086::cycles_t c0 = cpu.cycles();
    double s = 0;
    do {
        for (int i = 0; i < 50; ++i) {
            // run to the next INTR request (the INTA answer schedules the one after)
            cpu.run_until(board.next_irq > cpu.cycles() ? board.next_irq : cpu.cycles() + 1);
            if (cpu.cycles() >= board.next_irq) cpu.set_intr(true);
        }
        s = seconds_since(t0);
    } while (s < min_seconds);
    *cycles_out = cpu.cycles() - c0;
    return double(cpu.cycles() - c0) / s;
}

double bench_sst(const std::string& dir, double min_seconds, std::uint64_t* cycles_out, std::size_t* files) {
    using namespace i8086::sst;
    std::vector<std::vector<Test>> parsed;
    std::vector<nlohmann::json> docs;
    const auto list = collect({dir});
    docs.reserve(list.size());
    for (const auto& f : list) {
        docs.push_back(nlohmann::json::parse(read_text(f)));
        parsed.push_back(Runner::convert(docs.back(), f));
    }
    *files = parsed.size();
    Runner runner;
    std::uint64_t cycles = 0;
    const auto t0 = std::chrono::steady_clock::now();
    double s = 0;
    do {
        for (const auto& tests : parsed) cycles += runner.run_converted(tests);
        s = seconds_since(t0);
    } while (s < min_seconds);
    *cycles_out = cycles;
    return double(cycles) / s;
}

// Rounds alternate between the two emulators so that both see the same host load; the best
// round of each is compared (the least disturbed one). Returns false when the runs disagree.
bool bench_anchor(const std::string& image_path, unsigned rounds) {
    const std::vector<std::uint8_t> image = anchor::read_image(image_path);
    anchor::Outcome core, ref;
    double core_best = 0, ref_best = 0;
    for (unsigned i = 0; i < rounds; ++i) {
        core = anchor::run_core(image);
        ref = anchor::run_x86emu(image);
        if (i == 0 || core.cpu_seconds < core_best) core_best = core.cpu_seconds;
        if (i == 0 || ref.cpu_seconds < ref_best) ref_best = ref.cpu_seconds;
    }
    const double n = double(core.instructions);
    std::printf("anchor program: %s, %.2f M instructions\n", image_path.c_str(), n / 1e6);
    std::printf("rcsim core    : %8.1f M instructions/s  (cycle-exact; best of %u, host CPU time)\n",
                n / core_best / 1e6, rounds);
    std::printf("libx86emu     : %8.1f M instructions/s  (instruction level)\n", n / ref_best / 1e6);
    std::printf("ratio         : %8.2fx  (rcsim core / libx86emu, same image, same run)\n", ref_best / core_best);
    if (!(core == ref)) {
        std::printf("error: the two runs disagree (instructions %llu vs %llu, AX %04X vs %04X, checksum sum %u vs %u)\n",
                    static_cast<unsigned long long>(core.instructions), static_cast<unsigned long long>(ref.instructions),
                    core.ax, ref.ax, core.out_sum, ref.out_sum);
        return false;
    }
    return true;
}

} // namespace

void add_bench_cpu(CLI::App& bench) {
    auto dir = std::make_shared<std::string>();
    auto secs = std::make_shared<double>(2.0);
    auto* cmd = bench.add_subcommand("cpu", "8086 core: emulated cycles per host second (trace off)");
    cmd->add_option("--sst", *dir, "SingleStepTests folder for the instruction-stream figure (default: skip)");
    cmd->add_option("--seconds", *secs, "Minimum host time per measurement (0.1 .. 600)")->check(real_in(0.1, 600));
    auto anchor = std::make_shared<bool>(false);
    auto rounds = std::make_shared<unsigned>(3);
    auto image = std::make_shared<std::string>(RCSIM_BENCH_LOOP_IMAGE);
    cmd->add_flag("--anchor", *anchor, "Also run the core and libx86emu side by side on the same image; print the ratio");
    cmd->add_option("--rounds", *rounds, "Alternating rounds of the anchor comparison (best of each)")
        ->check(whole_in(1, 100));
    cmd->add_option("--image", *image, "8086 image for the anchor comparison (loaded at 1000:0000, ends with HLT)")
        ->capture_default_str();
    cmd->callback([dir, secs, anchor, rounds, image] {
        std::uint64_t cycles = 0;
        const double loop = bench_loop(*secs, &cycles);
        std::printf("protocol loop : %8.1f M cycles/s  (%llu cycles, %.1fx real time at 8 MHz)\n", loop / 1e6,
                    static_cast<unsigned long long>(cycles), loop / 8e6);
        if (!dir->empty()) {
            std::size_t files = 0;
            const double sst = bench_sst(*dir, *secs, &cycles, &files);
            std::printf("SST streams   : %8.1f M cycles/s  (%llu cycles over %zu files; includes per-test set-up)\n",
                        sst / 1e6, static_cast<unsigned long long>(cycles), files);
        }
        if (*anchor && !bench_anchor(*image, *rounds)) throw CLI::RuntimeError(1);
    });
}

} // namespace rcsim
