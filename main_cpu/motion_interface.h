// rcsim — the seam between the main CPU's token dispatcher and the motion layer.
//
// The dispatcher (main_cpu/) hands every motion token of docs/system.md §7.2 (kMotionTokens below,
// and ES) to a MotionInterface and sends back its reply as the response frame. The motion layer
// (main_cpu/motion/: PLCopen function blocks over the CAMC-QI chip and CiA402 drives) implements
// it; a dispatcher built without one answers BCH 04 ("not allowed in the current state").
#pragma once

#include <systemc>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rcsim {

/// A motion token of docs/system.md §7.2, and whether it starts a move: accepted (BCH 00), a move
/// token is paired with the move's first pulse (MoveRecord, the command latency).
struct MotionToken {
    std::string_view name;
    bool starts_move;
};

/// The one table of the motion tokens (ES, the emergency stop, is the dispatcher's own first).
inline constexpr MotionToken kMotionTokens[] = {
    {"SV", false}, {"HM", true}, {"RS", false}, {"MA", true}, {"MR", true},
    {"MV", true},  {"ML", true}, {"LM", true},  {"MC", true},
};

inline bool is_motion_token(std::string_view token) {
    for (const MotionToken& t : kMotionTokens)
        if (t.name == token) return true;
    return false;
}

inline bool starts_move(std::string_view token) {
    for (const MotionToken& t : kMotionTokens)
        if (t.name == token) return t.starts_move;
    return false;
}

/// The response to one command: BCH status (docs/system.md §7.1: 00 ok, 01 unknown token, 02 bad data,
/// 03 busy, 04 not allowed in the current state, 05 axis error) and response data.
struct MotionReply {
    std::uint8_t bch = 0;
    std::string data;
};

class MotionInterface {
public:
    virtual ~MotionInterface() = default;
    /// Executes or starts one motion command. Returns at once: a move is acknowledged when it is
    /// accepted, not when it is done. `token` is two characters, `data` the frame's data field.
    virtual MotionReply command(const std::string& token, const std::string& data) = 0;
    /// Called by the main CPU at the start of every control cycle (default 1 ms) at simulated time
    /// `now`; runs the function blocks and the drives.
    virtual void control_cycle(const sc_core::sc_time& now) = 0;
    /// Called just before control_cycle: the cycle's ideal start and, when it had to wait for the
    /// processor, the activity that held it then ("" when it was free), for the causes of a late
    /// cycle's effects (a missed CSP SYNC).
    virtual void cycle_context(const sc_core::sc_time& ideal, const std::string& held_by) {
        (void)ideal;
        (void)held_by;
    }
    /// Actual positions of the axes in pulses (for the ST token's response).
    virtual std::vector<std::int64_t> positions() const = 0;
    /// A short state text for the ST token (e.g. "STANDSTILL", "ERRORSTOP").
    virtual std::string state() const = 0;
};

} // namespace rcsim
