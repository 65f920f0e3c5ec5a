// rcsim — the seam between the main CPU's token dispatcher and a user program runtime (the
// Structured Text runtime of main_cpu/st/, docs/st.md): RN starts a program by name, SP stops it,
// ST reports its state, and the main CPU runs it once per control cycle.
#pragma once

#include <systemc>

#include <cstdint>
#include <string>

namespace rcsim {

/// What one execution of the program did, in the units the main CPU's cost model charges
/// (docs/st.md "Cost"): MainCpuConfig::statement_time per statement, fb_call per motion block.
struct ProgramWork {
    std::uint64_t statements = 0;   // statements executed plus loop iterations begun (the budget's count)
    std::uint64_t motion_calls = 0; // calls of the PLCopen motion blocks (MC_...) among them
};

class ProgramInterface {
public:
    virtual ~ProgramInterface() = default;
    /// Whether the loaded text has a PROGRAM of this name (case-insensitive).
    virtual bool has_program(const std::string& name) const = 0;
    /// Starts it from its initial values; "" when started, else why not.
    virtual std::string start(const std::string& name) = 0;
    /// Stops the running program (its variables stay readable).
    virtual void stop() = 0;
    virtual bool running() const = 0;
    /// The runtime error that stopped the program ("" if none).
    virtual const std::string& error() const = 0;
    /// One execution of the running program, after the motion layer's cycle at `now`; what it
    /// did (nothing when no program runs).
    virtual ProgramWork cycle(const sc_core::sc_time& now) = 0;
};

} // namespace rcsim
