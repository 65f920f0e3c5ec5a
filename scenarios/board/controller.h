// rcsim — the assembled two-CPU controller: the communication board and the main board joined by
// the IDT7130 (left port: 8086, INT_L -> 8259A IR3; right port: main CPU, INT_R -> main CPU).
// The main board is the behavioural main CPU with a slot for the motion layer (set_motion).
#pragma once

#include "dpram/idt7130.h"
#include "main_cpu/main_cpu.h"
#include "comm_cpu/comm_board.h"

namespace rcsim {

struct ControllerConfig {
    CommBoardConfig comm;
    MainCpuConfig main;
    unsigned dpram_speed_grade_ns = 55;
};

class Controller : public sc_core::sc_module {
public:
    CommBoard comm;
    Idt7130 dpram;
    MainCpu main;
    IrqLine int_l{"int_l"}, int_r{"int_r"};

    Controller(sc_core::sc_module_name name, const ControllerConfig& config = ControllerConfig());

    /// The motion layer in the main board's slot (nullptr: none; motion tokens answer BCH 04).
    void set_motion(MotionInterface* motion) { main.set_motion(motion); }
};

} // namespace rcsim
