// rcsim — `rcsim bench serial`: the cost of the serial path. N lines, each with an 82510 at both
// ends, saturated full duplex (both transmitters always busy) for a span of simulated time; an
// interrupt-driven pump at each end plays the CPU through the TLM socket (GIR, RXD, TXD). The
// figure is wall time against simulated time; the character counts check the run was saturated.
#include "uart82510/uart82510.h"

#include "models/bus.h"
#include "models/plumbing/cli_range.h"
#include "models/clock.h"

#include <CLI/CLI.hpp>
#include <tlm_utils/simple_initiator_socket.h>

#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <vector>

namespace rcsim {
namespace {

using namespace i82510;

/// Plays an interrupt service routine: on INT, reads GIR until nothing is pending, draining the
/// RX FIFO and refilling the TX FIFO. Runs as a method (no time passes: the pump is the load
/// generator, not a CPU model).
struct Pump : sc_core::sc_module {
    tlm_utils::simple_initiator_socket<Pump> sock{"sock"};
    IrqIn irq{"irq"};
    std::uint64_t received = 0, written = 0, accesses = 0;
    std::uint8_t next = 0;
    std::uint16_t divisor;

    Pump(sc_core::sc_module_name n, std::uint16_t div) : sc_module(n), divisor(div) {
        SC_HAS_PROCESS(Pump);
        SC_THREAD(setup);
        SC_METHOD(service);
        sensitive << irq.pos();
        dont_initialize();
    }
    std::uint8_t rd(unsigned off) {
        std::uint8_t d = 0;
        ++accesses;
        bus_access(sock, BusCycle::io_read, off << 1, &d, 1, sc_core::sc_time_stamp());
        return d;
    }
    void wr(unsigned off, std::uint8_t v) {
        ++accesses;
        bus_access(sock, BusCycle::io_write, off << 1, &v, 1, sc_core::sc_time_stamp());
    }
    void setup() {
        wr(LCR, LCR_DLAB);
        wr(BAL, static_cast<std::uint8_t>(divisor));
        wr(BAH, static_cast<std::uint8_t>(divisor >> 8));
        wr(LCR, 0x1B); // 8E1
        wr(BANK, 0x40);
        wr(IMD, 0x00);  // 4-byte RX FIFO
        wr(FMD, 0x20);  // RX request at 3 characters, TX request when empty
        wr(BANK, 0x00);
        wr(GER, (1u << rx_fifo) | (1u << tx_fifo));
    }
    void service() {
        for (std::uint8_t g = rd(GIR); !(g & 1); g = rd(GIR)) {
            if ((g & 0x0E) == 0x04) {
                while (rd(LSR) & LSR_DR) {
                    rd(RXD);
                    ++received;
                }
            } else if ((g & 0x0E) == 0x02) {
                for (int i = 0; i < 4; ++i) {
                    wr(TXD, next++);
                    ++written;
                }
            }
        }
    }
};

struct Link {
    SerialLine line;
    Uart82510 a, b;
    Pump pa, pb;
    IrqLine ia, ib;
    Link(const std::string& n, std::uint16_t div)
        : line((n + "_line").c_str()), a((n + "_a").c_str()), b((n + "_b").c_str()), pa((n + "_pa").c_str(), div),
          pb((n + "_pb").c_str(), div), ia((n + "_ia").c_str()), ib((n + "_ib").c_str()) {
        a.connect(line, SerialLine::a);
        b.connect(line, SerialLine::b);
        pa.sock.bind(a.bus);
        pb.sock.bind(b.bus);
        a.int_out.bind(ia);
        b.int_out.bind(ib);
        pa.irq.bind(ia);
        pb.irq.bind(ib);
    }
};

// The options' validators (add_bench_serial) have checked lines, baud and seconds.
void run_bench_serial(unsigned lines, unsigned baud, double seconds) {
    const std::uint64_t clock = Uart82510::Config{}.clock_hz;
    const auto div = static_cast<std::uint16_t>(clock / (32ULL * baud));
    std::vector<std::unique_ptr<Link>> links;
    for (unsigned i = 0; i < lines; ++i) links.push_back(std::make_unique<Link>("l" + std::to_string(i), div));

    const sc_core::sc_time span = ps(static_cast<std::uint64_t>(seconds * 1e12));
    const auto t0 = std::chrono::steady_clock::now(); // the harness's wall clock, not the model's
    sc_core::sc_start(span);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    std::uint64_t chars = 0, accesses = 0, overruns = 0, errors = 0;
    for (const auto& l : links) {
        chars += l->a.stats().chars_received + l->b.stats().chars_received;
        accesses += l->pa.accesses + l->pb.accesses;
        overruns += l->a.stats().overruns + l->b.stats().overruns;
        errors += l->a.stats().parity_errors + l->b.stats().parity_errors + l->a.stats().framing_errors +
                  l->b.stats().framing_errors;
    }
    const double per_dir = seconds * baud / 11.0; // 8E1: 11 bits a character
    std::cout << std::fixed << std::setprecision(3) << "bench serial: " << lines << " lines x 2 directions, " << baud
              << " bps 8E1, saturated, " << seconds << " s simulated\n"
              << "  wall time          " << wall << " s\n"
              << "  real-time factor   " << std::setprecision(1) << seconds / wall << "x\n"
              << "  characters         " << chars << " (line capacity " << std::setprecision(0)
              << per_dir * 2 * lines << ")\n"
              << "  bus accesses       " << accesses << "\n"
              << "  overruns / errors  " << overruns << " / " << errors << "\n"
              << std::setprecision(1) << "  per character      " << wall / static_cast<double>(chars) * 1e9
              << " ns wall\n";
}

} // namespace

void add_bench_serial(CLI::App& bench) {
    auto* cmd = bench.add_subcommand("serial", "82510 pairs saturated over bit-timed lines (issue 4)");
    static unsigned lines = 3, baud = 115200;
    static double seconds = 10.0;
    cmd->add_option("--lines", lines, "Lines, each with an 82510 at both ends")->capture_default_str()->check(whole_in(1, 64));
    cmd->add_option("--baud", baud, "Baud rate (exact divisor of 18.432 MHz / 32)")
        ->capture_default_str()
        ->check(whole_in(1, 576000))
        ->check(CLI::Validator(
            [](std::string& text) {
                const std::uint64_t clock = Uart82510::Config{}.clock_hz, b = std::stoull(text);
                return clock % (32 * b) == 0 && clock / (32 * b) <= 0xFFFF
                           ? std::string()
                           : "'" + text + "' is not an exact divisor rate of 18.432 MHz / 32";
            },
            "exact divisor"));
    cmd->add_option("--seconds", seconds, "Simulated time (0.001 .. 3600)")->capture_default_str()->check(real_in(0.001, 3600));
    cmd->callback([] { run_bench_serial(lines, baud, seconds); });
}

} // namespace rcsim
