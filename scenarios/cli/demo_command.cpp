// rcsim demo — the Intel 8259A and the IDT7130 at work, printed as a short timeline.
//
// A scripted communication CPU (8086-2 timings at 8 MHz) and a scripted main CPU drive the two
// chip models over TLM, wired as on the board: 82510 #0..#2 on IR0..IR2 (stand-ins that raise a
// request and withdraw it when read), DP-RAM INT_L on IR3. The firmware's use is shown:
//   1. four simultaneous requests served round-robin under rotate-on-non-specific-EOI (OCW2 0xA0),
//      with a new request on IR0 arriving mid-round;
//   2. a DP-RAM mailbox exchange (main CPU -> 0x3FE -> INT_L/IR3, comm CPU ACK -> 0x3FF -> INT_R);
//   3. both CPUs writing pflag[0] at once: BUSY, wait states, and no byte lost.
// Everything is simulated time; the output is the same on every run.
#include "dpram/idt7130.h"
#include "models/bus.h"
#include "models/clock.h"
#include "models/dpram_layout.h"
#include "models/plumbing/hex.h"
#include "models/irq.h"
#include "pic8259/pic8259.h"

#include <CLI/CLI.hpp>
#include <systemc>
#include <tlm_utils/simple_initiator_socket.h>

#include <array>
#include <cstdio>
#include <iostream>
#include <ostream>
#include <string>
#include <vector>

namespace rcsim {

int run_demo(std::ostream& out);
void add_demo_command(CLI::App& app);

namespace {

// 8086-2 figures used by the scripted comm CPU, in clocks of 125 ns (docs/cpu8086.md "Published
// timing facts").
constexpr cycles_t kIoInstruction = 9;   // OUT/IN DX: 8 clocks + the board's 1 I/O wait state
constexpr cycles_t kToFirstInta = 2;     // INTR seen in HLT -> T1 of INTA #1 (assumed)
constexpr cycles_t kInterInta = 6;       // T1 of INTA #1 -> T1 of INTA #2: 4-clock cycle + 2 idle (assumed)
constexpr cycles_t kInterruptEntry = 61; // INTR seen -> first handler instruction (quoted, unconfirmed)
constexpr cycles_t kHandlerBody = 120;   // what a short receive handler does between device read and EOI
constexpr cycles_t kIret = 32;

constexpr std::uint8_t kVectorBase = 0x20;
constexpr std::uint8_t kRotateOnEoi = 0xA0;
constexpr unsigned kPflag0 = dpram_layout::pflag_addr(0); // docs/system.md §4.1
constexpr unsigned kServices = 5;

/// Simulated time as microseconds with nanosecond digits, from integer picoseconds.
std::string stamp(const sc_core::sc_time& t, int width = 0) {
    const std::uint64_t ns = t.value() / 1000;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%*llu.%03llu us", width, static_cast<unsigned long long>(ns / 1000),
                  static_cast<unsigned long long>(ns % 1000));
    return buf;
}

std::string hex0x(unsigned v, unsigned digits = 2) { return "0x" + hex(v, digits); }

/// The timeline: one line per event, stamped with the simulated time it is written at.
class Timeline {
public:
    explicit Timeline(std::ostream& out) : out_(out) {}
    void log(const std::string& what) { out_ << stamp(sc_core::sc_time_stamp(), 7) << "  " << what << "\n"; }
    std::ostream& raw() { return out_; }

private:
    std::ostream& out_;
};

/// Stands in for an 82510's interrupt output: raised at given times, withdrawn when the CPU reads
/// the chip (its only writer, so the line has a single driver).
class RequestSource : public sc_core::sc_module {
public:
    IrqOut irq{"irq"};

    RequestSource(sc_core::sc_module_name name, std::vector<sc_core::sc_time> raise_at)
        : sc_module(name), raise_at_(std::move(raise_at)) {
        SC_HAS_PROCESS(RequestSource);
        SC_THREAD(run);
    }
    void read_by_cpu() { read_.notify(sc_core::SC_ZERO_TIME); }

private:
    std::vector<sc_core::sc_time> raise_at_;
    sc_core::sc_event read_;

    void run() {
        for (const auto& t : raise_at_) {
            if (t > sc_core::sc_time_stamp()) sc_core::wait(t - sc_core::sc_time_stamp());
            irq.write(true);
            sc_core::wait(read_);
            irq.write(false);
        }
    }
};

class DemoBoard : public sc_core::sc_module {
public:
    Pic8259 pic{"pic"};
    Idt7130 dpram{"dpram"};
    RequestSource uart0, uart1, uart2;
    tlm_utils::simple_initiator_socket<DemoBoard> io{"io"};
    tlm_utils::simple_initiator_socket<DemoBoard> inta{"inta"};
    tlm_utils::simple_initiator_socket<DemoBoard> left{"left"};   // comm CPU memory bus -> DP-RAM
    tlm_utils::simple_initiator_socket<DemoBoard> right{"right"}; // main CPU -> DP-RAM
    sc_core::sc_vector<IrqLine> ir{"ir", 8};
    IrqLine intr{"intr"};
    IrqLine int_r{"int_r"};
    Clock clock{8'000'000};

    std::vector<unsigned> order;
    BusResult pflag_left, pflag_right;

    DemoBoard(sc_core::sc_module_name name, Timeline& timeline)
        : sc_module(name),
          uart0("uart0", {us(20) + ns(500), us(60)}), // a second character on port 0 mid-round
          uart1("uart1", {us(20) + ns(500)}),
          uart2("uart2", {us(20) + ns(500)}),
          tl_(timeline) {
        io.bind(pic.bus);
        inta.bind(pic.inta);
        left.bind(dpram.left);
        right.bind(dpram.right);
        for (unsigned n = 0; n < 8; ++n) pic.ir[n].bind(ir[n]);
        uart0.irq.bind(ir[0]);
        uart1.irq.bind(ir[1]);
        uart2.irq.bind(ir[2]);
        dpram.int_l.bind(ir[3]);
        dpram.int_r.bind(int_r);
        pic.intr.bind(intr);
        pic.on_inta = [this](const Pic8259::IntaEvent& e) { on_inta(e); };
        dpram.on_busy = [this](const Idt7130::BusyEvent& e) { on_busy(e); };

        SC_HAS_PROCESS(DemoBoard);
        SC_THREAD(comm_cpu);
        SC_THREAD(main_cpu);
        SC_METHOD(watch_requests);
        for (unsigned n = 0; n < 4; ++n) sensitive << ir[n].value_changed_event();
        sensitive << int_r.value_changed_event();
        dont_initialize();
    }

private:
    Timeline& tl_;
    std::array<bool, 4> ir_seen_{};
    bool int_r_seen_ = false;

    void wait_clocks(cycles_t n) { sc_core::wait(clock.cycles(n)); }
    /// To the next clock edge (the CPU samples INTR on clock edges).
    void align() {
        const std::uint64_t rem = sc_core::sc_time_stamp().value() % clock.period_ps();
        if (rem) sc_core::wait(ps(clock.period_ps() - rem));
    }
    void out(bool a0, std::uint8_t value) {
        bus_access(io, BusCycle::io_write, a0 ? 2 : 0, &value, 1, sc_core::sc_time_stamp());
        wait_clocks(kIoInstruction);
    }
    BusResult mem(tlm_utils::simple_initiator_socket<DemoBoard>& s, bool write, unsigned address,
                  std::uint8_t& value, int who) {
        const BusResult r = bus_access(s, write ? BusCycle::mem_write : BusCycle::mem_read, address, &value, 1,
                                       sc_core::sc_time_stamp(), who);
        if (!r.ok()) SC_REPORT_ERROR("rcsim/demo", ("DP-RAM access to " + hex0x(address, 3) + " failed").c_str());
        return r;
    }

    void watch_requests() {
        static const char* const source[4] = {"82510 #0", "82510 #1", "82510 #2", "DP-RAM INT_L"};
        for (unsigned n = 0; n < 4; ++n) {
            const bool v = ir[n].read();
            if (v != ir_seen_[n])
                tl_.log("IR" + std::to_string(n) + (v ? " requested by " : " withdrawn by ") +
                        source[n]);
            ir_seen_[n] = v;
        }
        if (int_r.read() != int_r_seen_) {
            int_r_seen_ = int_r.read();
            tl_.log(std::string("INT_R ") + (int_r_seen_ ? "asserted (main CPU interrupted)" : "released"));
        }
    }

    void on_inta(const Pic8259::IntaEvent& e) {
        if (e.cycle == 1)
            tl_.log("INTA #1: IR" + std::to_string(e.level) + (e.spurious ? " (spurious)" : "") + " in service, ISR " +
                    hex0x(pic.isr()) + ", IRR " + hex0x(pic.irr()));
        else
            tl_.log("INTA #2: vector " + hex0x(e.data));
    }

    void on_busy(const Idt7130::BusyEvent& e) {
        tl_.log(std::string("BUSY_") + (e.port == Idt7130::left_port ? "L" : "R") + " on " + hex0x(e.address, 3) +
                ": low at " + stamp(e.busy_low) + ", high at " + stamp(e.busy_high) + " -> " +
                std::to_string(e.wait_states) + " wait state(s) for the " + to_string(e.port) + " port's " +
                (e.write ? "write" : "read"));
    }

    void comm_cpu() {
        out(false, 0x13); // ICW1: edge triggered, single, ICW4 follows
        out(true, kVectorBase);
        out(true, 0x01);  // ICW4: 8086 mode, normal EOI
        out(true, 0xF0);  // OCW1: IR0..IR3 enabled
        tl_.log("comm CPU: 8259A initialised (ICW1 0x13, ICW2 0x20, ICW4 0x01, OCW1 0xF0), HLT");

        while (order.size() < kServices) {
            if (!intr.read()) sc_core::wait(intr.posedge_event()); // HLT until INTR
            align();
            const sc_core::sc_time seen = sc_core::sc_time_stamp();
            wait_clocks(kToFirstInta);
            std::uint8_t v = 0xFF;
            bus_access(inta, BusCycle::int_ack, 0, &v, 1, sc_core::sc_time_stamp());
            wait_clocks(kInterInta);
            bus_access(inta, BusCycle::int_ack, 0, &v, 1, sc_core::sc_time_stamp());
            sc_core::wait(seen + clock.cycles(kInterruptEntry) - sc_core::sc_time_stamp());
            const unsigned level = v - kVectorBase;
            order.push_back(level);
            handler(level);
            tl_.log("comm CPU: EOI " + hex0x(kRotateOnEoi) + " (rotate): IR" + std::to_string(level) +
                    " now lowest, IR" + std::to_string((level + 1) & 7) + " highest");
            out(false, kRotateOnEoi);
            wait_clocks(kIret);
        }

        // pflag[0] at the same moment as the main CPU (see main_cpu).
        sc_core::wait(us(250) - sc_core::sc_time_stamp());
        std::uint8_t flag = 1; // EXT_USE
        pflag_left = mem(left, true, kPflag0, flag, Idt7130::left_port);
        tl_.log("comm CPU: writes pflag[0] = 0x01 (EXT_USE), " + std::to_string(pflag_left.wait_states) +
                " wait state(s)");
    }

    void handler(unsigned level) {
        tl_.log("comm CPU: handler IR" + std::to_string(level) + " entered");
        if (level < 3) {
            RequestSource* uart[3] = {&uart0, &uart1, &uart2};
            uart[level]->read_by_cpu(); // reading the receive buffer withdraws the request
            wait_clocks(kHandlerBody);
            return;
        }
        std::uint8_t word = 0, data = 0;
        mem(left, false, Idt7130::kMailboxLeft, word, Idt7130::left_port);
        wait_clocks(4);
        mem(left, false, 0x000, data, Idt7130::left_port);
        tl_.log("comm CPU: read int2ext = " + hex0x(word) + ", data[0][0] = " + hex0x(data));
        wait_clocks(kHandlerBody);
        std::uint8_t ack = static_cast<std::uint8_t>(0x20 | (word & 0x0F));
        mem(left, true, Idt7130::kMailboxRight, ack, Idt7130::left_port);
        tl_.log("comm CPU: writes int2rbt = " + hex0x(ack) + " (ACK)");
        wait_clocks(4);
    }

    void main_cpu() {
        sc_core::wait(us(20) - ns(500));
        std::uint8_t soh = 0x01, word = 0x10;
        mem(right, true, 0x000, soh, Idt7130::right_port);
        sc_core::wait(ns(500));
        mem(right, true, Idt7130::kMailboxLeft, word, Idt7130::right_port);
        tl_.log("main CPU: writes data[0][0] = 0x01, then int2ext = 0x10 (new chunk, port 0)");

        sc_core::wait(int_r.posedge_event());
        sc_core::wait(us(2));
        std::uint8_t ack = 0;
        mem(right, false, Idt7130::kMailboxRight, ack, Idt7130::right_port);
        tl_.log("main CPU: reads int2rbt = " + hex0x(ack));

        sc_core::wait(us(250) + ns(100) - sc_core::sc_time_stamp());
        std::uint8_t flag = 2; // RBT_USE
        pflag_right = mem(right, true, kPflag0, flag, Idt7130::right_port);
        tl_.log("main CPU: writes pflag[0] = 0x02 (RBT_USE), " + std::to_string(pflag_right.wait_states) +
                " wait state(s)");
    }
};

} // namespace

int run_demo(std::ostream& out) {
    Timeline tl(out);
    DemoBoard board("board", tl);
    out << "rcsim demo: Intel 8259A + IDT7130, 8086-2 at 8 MHz (125 ns clock), simulated time\n";
    sc_core::sc_start();

    const Pic8259& pic = board.pic;
    const Idt7130& ram = board.dpram;
    out << "service order:";
    for (unsigned level : board.order) out << " IR" << level;
    out << "\n";
    out << "8259A acknowledges: IR0=" << pic.acks(0) << " IR1=" << pic.acks(1) << " IR2=" << pic.acks(2)
        << " IR3=" << pic.acks(3) << " spurious=" << pic.spurious_acks() << "\n";
    out << "IDT7130: collisions=" << ram.collisions() << ", BUSY wait left=" << ram.stats(Idt7130::left_port).wait_states
        << " right=" << ram.stats(Idt7130::right_port).wait_states << " clock(s), pflag[0] = "
        << hex0x(ram.peek(kPflag0)) << " (the later write landed last, none lost)\n";
    const bool ok = board.order.size() == kServices && ram.collisions() == 1 && !ram.int_l_pending() &&
                    !ram.int_r_pending();
    return ok ? 0 : 1;
}

void add_demo_command(CLI::App& app) {
    auto* demo = app.add_subcommand("demo", "Show the 8259A and IDT7130 models at work: a short timeline");
    demo->callback([] {
        const int rc = run_demo(std::cout);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
}

} // namespace rcsim
