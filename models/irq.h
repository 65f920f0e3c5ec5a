// rcsim — interrupt lines.
//
// An interrupt line is an sc_signal<bool> (active high, as the 8259A IR inputs and INTR; open-drain
// active-low pins such as the IDT7130 INT are modelled as "asserted = true"). sc_signal updates in
// the update phase, so every writer at one instant is seen together; receivers then re-evaluate
// through a Settler — a zero-time event that coalesces, as MAME's TIMER_CHECK_IRQ does — so that
// several lines changing in the same instant are decided on once, after all have settled.
#pragma once

#include <systemc>

namespace rcsim {

using IrqLine = sc_core::sc_signal<bool>;
using IrqIn = sc_core::sc_in<bool>;
using IrqOut = sc_core::sc_out<bool>;

/// A coalescing zero-time re-evaluation request. Call request() from any process; the owning
/// module has an SC_METHOD sensitive to event() that recomputes its outputs once per delta.
class Settler {
public:
    explicit Settler(const char* name) : ev_(name) {}
    void request() { ev_.notify(sc_core::SC_ZERO_TIME); } // later requests in the same delta merge
    const sc_core::sc_event& event() const { return ev_; }

private:
    sc_core::sc_event ev_;
};

} // namespace rcsim
