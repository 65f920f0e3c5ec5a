// rcsim — a loaded Structured Text program on the main CPU (docs/st.md): compiled once, started
// by name (RN), executed once per control cycle after the motion layer's cycle, stopped by SP or
// by a runtime error. A runtime error stops the program with its message and puts every axis in
// ErrorStop (ErrorID program_error); SP decelerates the axes that are moving.
#pragma once

#include "main_cpu/program_interface.h"
#include "main_cpu/st/compiler.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rcsim::motion {
class McAxis;
class MC_Power;
} // namespace rcsim::motion

namespace rcsim::st {

/// The ErrorID an axis gets when the program stops on a runtime error.
constexpr std::uint16_t program_error = 0x7201;

class StProgram : public ProgramInterface {
public:
    struct Config {
        std::uint64_t budget = 100000; // statements per cycle before the program is stopped
    };

    /// Compiles `text` (named `file` in messages) for these axes (AXIS_REF n = axes[n]; `power`,
    /// if given, the motion layer's own MC_Power per axis). Throws CompileError.
    StProgram(const std::string& text, const std::string& file, std::vector<motion::McAxis*> axes,
              std::vector<motion::MC_Power*> power = {});
    StProgram(const std::string& text, const std::string& file, std::vector<motion::McAxis*> axes,
              std::vector<motion::MC_Power*> power, Config cfg);
    ~StProgram() override;

    // ProgramInterface
    bool has_program(const std::string& name) const override;
    std::string start(const std::string& name) override;
    void stop() override;
    bool running() const override { return running_; }
    const std::string& error() const override { return error_; }
    ProgramWork cycle(const sc_core::sc_time& now) override;

    /// One execution at time `now_us` (microseconds); cycle() calls it. What it did: the
    /// statements up to and including one that failed (nothing when no program runs).
    ProgramWork run_once(std::int64_t now_us);

    const Unit& unit() const { return *unit_; }
    /// The PROGRAM last started ("" before the first RN).
    const std::string& current() const { return current_; }
    std::uint64_t cycles() const { return cycles_; }
    std::uint64_t max_statements() const { return max_statements_; }

    /// A variable of the program or a global: "x", "a[3]", "t1.Q", "p.x" (a STRUCT's member);
    /// throws std::out_of_range for a name that is not there or not a single value (a STRING,
    /// a whole STRUCT: variables() shows those). BOOL/integers/TIME (microseconds)/AXIS_REF in .i, REAL in .r.
    Value value(const std::string& path) const;
    /// Writes one (a test or a monitor forcing an input); no type check beyond the path's.
    void set_value(const std::string& path, Value v);
    /// The program's and the globals' variables (FB instances: their inputs and outputs), by name.
    nlohmann::json variables() const;
    /// state, program, error, cycles, max statements per cycle, variables.
    nlohmann::json report() const;

private:
    std::unique_ptr<Unit> unit_;
    ExecContext ctx_;
    std::unique_ptr<Instance> globals_, program_;
    std::string current_, error_;
    bool running_ = false;
    std::uint64_t cycles_ = 0, max_statements_ = 0;

    void fail(const std::string& message);
    Value* locate(const std::string& path);
};

} // namespace rcsim::st
