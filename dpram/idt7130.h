// rcsim — IDT7130 1K x 8 dual-port static RAM (MASTER: on-chip BUSY arbitration, mailbox INT).
//
// Source: IDT7130/7140 data sheet (DSC-2689) functional description and truth tables, with BUSY
// timing figures from the same IDT family (IDT70121, IDT7016) because the 7130's own AC table was
// not available — see dpram/README.md for the sources and the assumptions.
//
//   left  (TLM target) <-- communication CPU, 8086-2 @ 8 MHz   INT_L --> 8259A IR3
//   right (TLM target) <-- main CPU                            INT_R --> main CPU
//
// Mailboxes: right write 0x3FE sets INT_L, left read 0x3FE clears it; left write 0x3FF sets INT_R,
// right read 0x3FF clears it. A port writing its own mailbox does nothing.
//
// BUSY: the chip select of an access is active for the whole bus cycle of its port, the window
// [start, start + cycle_clocks * clock). When the other port's window on the same location is
// still open, the access being decided now is the one whose address became stable later, so it
// gets BUSY (never both). Its read or write completes tBDD / tWH after BUSY rises, tBDA after the
// winner's cycle ends; the extra time reaches the initiator as wait states of its own clock.
// Transactions are decided in simulated-time order, which the bus convention guarantees (each
// initiator syncs before a DP-RAM access).
#pragma once

#include "models/bus.h"
#include "models/irq.h"

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_target_socket.h>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace rcsim {

class Idt7130 : public sc_core::sc_module, public StableReads {
public:
    static constexpr unsigned kSize = 1024;
    static constexpr unsigned kMailboxLeft = 0x3FE;  // message to the left CPU (INT_L)
    static constexpr unsigned kMailboxRight = 0x3FF; // message to the right CPU (INT_R)

    enum Port : unsigned { left_port = 0, right_port = 1 };

    /// BUSY timing of the arbiter (data sheet symbols).
    struct BusyTiming {
        sc_core::sc_time t_aps; // arbitration priority set-up: closer starts have an unspecified winner
        sc_core::sc_time t_baa; // BUSY low after the address match
        sc_core::sc_time t_bda; // BUSY high after the winner's address stops matching
        sc_core::sc_time t_bdd; // loser's read data valid after BUSY high
        sc_core::sc_time t_wh;  // loser's write must be held after BUSY high to complete
    };

    /// How one port's initiator runs its bus cycles.
    struct PortTiming {
        sc_core::sc_time clock;    // period of the initiator's clock; wait states are counted in it
        unsigned cycle_clocks = 4; // clocks of a zero-wait cycle; CE is active for all of them, and the
                                   // data phase ends with the second-to-last (T3 of an 8086 cycle)
    };

    /// One BUSY episode, for probes and the demo.
    struct BusyEvent {
        Port port;                  // the port that got BUSY
        unsigned address;           // the contested location
        bool write;                 // the losing access
        sc_core::sc_time busy_low;  // BUSY asserted (later start + tBAA)
        sc_core::sc_time busy_high; // BUSY released (winner's cycle end + tBDA)
        unsigned wait_states;       // what the losing initiator saw
    };

    struct PortStats {
        std::uint64_t accesses = 0;
        std::uint64_t busy = 0;        // accesses of this port that got BUSY
        std::uint64_t wait_states = 0; // Tw inserted by BUSY, in this port's clocks
        sc_core::sc_time busy_wait;    // the same as time
    };

    tlm_utils::simple_target_socket<Idt7130> left;
    tlm_utils::simple_target_socket<Idt7130> right;
    IrqOut int_l; // true = asserted (pin low)
    IrqOut int_r;

    /// Property: the grade's BUSY timing, set from the speed grade by the constructor and by
    /// set_speed_grade(); may be overridden field by field afterwards.
    BusyTiming timing;
    /// Property: per port (index Port) clock and cycle length. Default for both: 8 MHz, 4 clocks.
    std::array<PortTiming, 2> ports;

    /// Probe hook, called when an access is given BUSY.
    std::function<void(const BusyEvent&)> on_busy;

    /// speed_grade_ns: 20, 25, 35, 55 or 100 (max access time); anything else is an SC_REPORT_ERROR.
    explicit Idt7130(sc_core::sc_module_name name, unsigned speed_grade_ns = 55);

    /// The assumed BUSY timing of a speed grade (see README.md); SC_REPORT_ERROR for an unknown grade.
    static BusyTiming grade_timing(unsigned speed_grade_ns);
    void set_speed_grade(unsigned speed_grade_ns);
    unsigned speed_grade() const { return grade_; }

    /// Board reset: both mailbox interrupts cleared. The RAM keeps its contents (there is no reset pin
    /// on the chip; SRAM content survives a CPU reset).
    void reset();

    /// The left port's stable reads (models/bus.h): every location but the left mailbox 0x3FE,
    /// whose read clears INT_L. A location's value changes only by a write of either port, each
    /// decided at its initiator's kernel event; the BUSY window and the counters of a read
    /// follow its T1 (BusExtension::start), never sc_time_stamp().
    bool read_is_stable(std::uint64_t address, unsigned len) const override {
        return address + len <= kSize && !(address <= kMailboxLeft && kMailboxLeft < address + len);
    }

    // Side-effect-free state.
    std::uint8_t peek(unsigned address) const { return mem_.at(address); }
    bool int_l_pending() const { return int_l_; }
    bool int_r_pending() const { return int_r_; }

    // Counters.
    const PortStats& stats(Port port) const { return stats_.at(port); }
    /// BUSY episodes, both ports together.
    std::uint64_t collisions() const { return stats_[0].busy + stats_[1].busy; }
    /// Of those, the ones whose starts were closer than tAPS (the data sheet leaves the winner open;
    /// the model gives it to the access decided first).
    std::uint64_t collisions_inside_aps() const { return inside_aps_; }

private:
    struct Window {
        bool valid = false;
        unsigned first = 0, last = 0; // locations touched
        sc_core::sc_time start, end;  // CE active; end includes BUSY wait states
    };
    struct PinChange {
        sc_core::sc_time when;
        bool left;  // INT_L (else INT_R)
        bool value;
    };

    std::array<std::uint8_t, kSize> mem_{};
    unsigned grade_ = 55;
    bool int_l_ = false, int_r_ = false;
    std::array<Window, 2> last_{};
    std::array<PortStats, 2> stats_{};
    std::uint64_t inside_aps_ = 0;
    std::vector<PinChange> pin_changes_;
    sc_core::sc_event pins_event_;

    void end_of_elaboration() override;

    void b_transport_left(tlm::tlm_generic_payload& gp, sc_core::sc_time&) { access(left_port, gp); }
    void b_transport_right(tlm::tlm_generic_payload& gp, sc_core::sc_time&) { access(right_port, gp); }
    unsigned transport_dbg(tlm::tlm_generic_payload& gp);

    void access(Port port, tlm::tlm_generic_payload& gp);
    bool check(Port port, tlm::tlm_generic_payload& gp);
    unsigned arbitrate(Port port, const Window& mine, bool write);
    void mailbox(Port port, unsigned address, bool write, const sc_core::sc_time& end);
    void schedule_pin(bool left_pin, bool value, const sc_core::sc_time& when);
    void drive_pins();
};

const char* to_string(Idt7130::Port port);

} // namespace rcsim
