// rcsim — the waveforms of `rcsim run --vcd FILE` (docs/tools.md "VCD waveforms").
//
// Signals, all with SystemC's VCD writer (sc_trace), one bit each:
//   ir0..ir2, ir3_int_l   the 8259A's IR inputs (82510 #0..#2 INT, DP-RAM INT_L), true = request
//   int_r                 DP-RAM INT_R to the main CPU, true = asserted (pin low)
//   intr                  the 8259A's INT output, wired to the 8086's INTR
//   inta                  the 8086's INTA#, true = asserted: T2 and T3 of each INTA bus cycle
//                         (8086 data sheet: "active LOW during T2, T3 and Tw"; the PIC adds no Tw)
//   portN_txd, portN_rxd  the 82510 #N's TXD and RXD pin levels, bit by bit (1 = MARK), a BREAK
//                         holding the wire at 0 for its length
//   dpram_busy_l/_r       the IDT7130's BUSY_L / BUSY_R, true = asserted (pin low)
// The serial wires, INTA and BUSY are not signals of the models (the line carries whole
// characters, the bus is TLM): they are rebuilt here from the models' probe hooks
// (SerialLine::on_transmit / on_break_level, Pic8259::on_inta, Idt7130::on_busy) as level
// changes scheduled at the times the hooks report, and written by one SC_METHOD. Nothing here
// feeds back into the models, so a run's report is the same with and without a trace.
#pragma once

#include "models/serial_line.h"

#include <systemc>

#include <map>
#include <string>
#include <vector>

namespace rcsim {

class World;

class VcdTrace : public sc_core::sc_module {
public:
    /// Opens `path`, a name ending in ".vcd" (scenarios/report/output.h open_vcd; throws
    /// ConfigError when it cannot be written) and hooks the world. Call before sc_start().
    VcdTrace(sc_core::sc_module_name name, World& world, const std::string& path);
    ~VcdTrace() override;

    /// Writes the last values and closes the file (also done by the destructor).
    void close();

private:
    enum class Input : unsigned char { level, hold };
    struct Wire {
        bool level = true; // what its driver puts out
        bool held = false; // a BREAK holds it at 0
        bool dirty = false;
    };
    struct Change {
        unsigned wire;
        Input input;
        bool value;
    };

    sc_core::sc_trace_file* file_ = nullptr;
    sc_core::sc_vector<sc_core::sc_signal<bool>> signals_;
    std::vector<Wire> wires_;
    std::multimap<sc_core::sc_time, Change> pending_; // equal times keep their order
    sc_core::sc_event wake_;
    sc_core::sc_time clock_; // the 8086's clock period

    void schedule(const sc_core::sc_time& at, unsigned wire, Input input, bool value);
    void trace_line(SerialLine& line, unsigned txd, unsigned rxd);
    void apply();
};

} // namespace rcsim
