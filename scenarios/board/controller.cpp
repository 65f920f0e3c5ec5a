#include "scenarios/board/controller.h"

#include "models/dpram_layout.h"

namespace rcsim {

// The layout both boards use puts its mailboxes where the IDT7130 has them.
static_assert(dpram_layout::int2ext == Idt7130::kMailboxLeft, "int2ext is the left port's mailbox (INT_L)");
static_assert(dpram_layout::int2rbt == Idt7130::kMailboxRight, "int2rbt is the right port's mailbox (INT_R)");

Controller::Controller(sc_core::sc_module_name name, const ControllerConfig& cfg)
    : sc_module(name), comm("comm", cfg.comm), dpram("dpram", cfg.dpram_speed_grade_ns),
      main("main", cfg.main) {
    // Each port's wait states are counted in its own initiator's clock.
    dpram.ports[Idt7130::left_port].clock = comm.cpu.clock().period();
    dpram.ports[Idt7130::right_port].clock = Clock(cfg.main.bus_clock_hz).period();
    dpram.ports[Idt7130::right_port].cycle_clocks = cfg.main.access_cycles;
    dpram.int_l(int_l);
    dpram.int_r(int_r);
    comm.connect_dpram(dpram, int_l);
    main.dpram.bind(dpram.right);
    main.int_r(int_r);
}

} // namespace rcsim
