// rcsim — the main CPU's token dispatcher: docs/system.md §7, one response per command.
//
// Plain C++ (no kernel): the MainCpu module charges the processing time and moves the frames; this
// class only decides. It keeps the controller's application state — a parameter table, stored
// programs, teach points, the program state — and hands the motion tokens to a MotionInterface.
// Without one, motion tokens answer BCH 04 with a note saying why.
#pragma once

#include "models/frame_codec.h"
#include "main_cpu/motion_interface.h"
#include "main_cpu/program_interface.h"

#include <cstdint>
#include <map>
#include <string>

namespace rcsim {

/// BCH status codes of docs/system.md §7.1.
namespace bch {
constexpr std::uint8_t ok = 0x00;
constexpr std::uint8_t unknown_token = 0x01;
constexpr std::uint8_t bad_data = 0x02;
constexpr std::uint8_t busy = 0x03;
constexpr std::uint8_t not_allowed = 0x04;
constexpr std::uint8_t axis_error = 0x05;
} // namespace bch

/// What one command produced: the response status and data, and for any refusal a short note
/// saying why (the module logs it).
struct Outcome {
    std::uint8_t bch = bch::ok;
    std::string data;
    std::string note;
};

struct TeachPoint {
    std::int64_t x = 0, y = 0, z = 0, r = 0;
};

enum class ProgramState { idle, running, halted, error };
const char* to_string(ProgramState s);

class Dispatcher {
public:
    void set_motion(MotionInterface* motion) { motion_ = motion; }
    MotionInterface* motion() const { return motion_; }
    /// The loaded user program (docs/st.md): RN of one of its PROGRAMs starts it, SP stops it.
    void set_program(ProgramInterface* program) { program_ = program; }
    ProgramInterface* program() const { return program_; }

    /// Executes one command (token and data of a validated frame).
    Outcome execute(const std::string& token, const std::string& data);

    /// RUNNING while a started program runs; a loaded program stopped by a runtime error: ERROR.
    ProgramState program_state() const;
    const std::map<long, std::int64_t>& parameters() const { return parameters_; }
    const std::map<std::string, std::string>& programs() const { return programs_; }

    /// Longest program or teach point name.
    static constexpr std::size_t max_name = 16;
    /// Highest parameter id.
    static constexpr long max_param_id = 65535;

private:
    Outcome echo(const std::string& data);
    Outcome state(const std::string& data);
    Outcome param_read(const std::string& data);
    Outcome param_write(const std::string& data);
    Outcome program_upload(const std::string& data);
    Outcome program_download(const std::string& data);
    Outcome teach_point(const std::string& data);
    Outcome teach_read(const std::string& data);
    Outcome run(const std::string& data);
    Outcome halt(const std::string& data);
    Outcome stop(const std::string& data);
    Outcome run_loaded(const std::string& name);
    Outcome emergency_stop(const std::string& data);
    Outcome motion_command(const std::string& token, const std::string& data);

    MotionInterface* motion_ = nullptr;
    ProgramInterface* program_ = nullptr;
    bool loaded_current_ = false; // the current program is the loaded one, not a PU text
    std::map<long, std::int64_t> parameters_;
    std::map<std::string, std::string> programs_;
    std::map<std::string, TeachPoint> points_;
    ProgramState program_state_ = ProgramState::idle;
    std::string current_program_;
};

} // namespace rcsim
