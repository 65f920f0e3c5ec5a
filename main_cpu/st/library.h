// rcsim — the blocks a Structured Text program gets without declaring them: the IEC 61131-3
// standard function blocks (R_TRIG, F_TRIG, SR, RS, CTU, CTD, CTUD written in ST as the standard's
// §6.6.3 tables give them; TON, TOF and TP in C++, they need the cycle's time) and the PLCopen motion
// blocks of main_cpu/motion/plcopen.h on AXIS_REF inputs (mc_blocks.cpp).
#pragma once

#include "main_cpu/st/ast.h"

#include <string>

namespace rcsim::st {

struct Unit;

/// Adds variables to a native block's layout.
struct PouBuilder {
    PouType& pou;
    std::size_t add(const std::string& name, VarKind kind, Kind type, Value init = {});
};

/// The standard blocks written in ST (compiled with every program).
const std::string& standard_prelude();
/// TON, TOF and TP.
void add_timer_blocks(Unit& u);
/// MC_Power, MC_Reset, MC_Home, MC_MoveAbsolute, MC_MoveRelative, MC_MoveVelocity, MC_Stop,
/// MC_Halt, MC_LineMove2, MC_LineMove (2-4 axes), MC_CircleCenterMove.
void add_motion_blocks(Unit& u);
/// MC_ReadActualVelocity, MC_Jog, MC_MoveSuperimposed (mc_manual.cpp).
void add_manual_motion_blocks(Unit& u);
/// MC_MoveSuperimposed's ErrorID on an axis that moves: the CAMC-QI cannot add a distance to a
/// running drive (docs/st.md "Motion blocks").
constexpr std::uint16_t superimposed_in_motion = 0x7202;

} // namespace rcsim::st
