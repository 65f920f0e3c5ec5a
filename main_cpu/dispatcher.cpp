// rcsim — token dispatcher (see dispatcher.h).
#include "main_cpu/dispatcher.h"

#include <charconv>
#include <vector>

namespace rcsim {

namespace {

Outcome refuse(std::uint8_t code, std::string note) { return Outcome{code, "", std::move(note)}; }

/// Splits on ',' (docs/system.md §5.3: fields separated by commas); "" gives one empty field.
std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out(1);
    for (char c : s) {
        if (c == ',')
            out.emplace_back();
        else
            out.back() += c;
    }
    return out;
}

/// A decimal integer with an optional leading '-', the whole field and nothing else.
bool parse_int(const std::string& s, std::int64_t& out) {
    if (s.empty()) return false;
    const char* end = s.data() + s.size();
    auto [ptr, ec] = std::from_chars(s.data(), end, out);
    return ec == std::errc() && ptr == end;
}

/// Program and teach point names: 1..16 of [A-Za-z0-9_].
bool valid_name(const std::string& s) {
    if (s.empty() || s.size() > Dispatcher::max_name) return false;
    for (char c : s) {
        const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                        c == '_';
        if (!ok) return false;
    }
    return true;
}

bool parse_param_id(const std::string& s, long& id) {
    std::int64_t v = 0;
    if (!parse_int(s, v) || v < 0 || v > Dispatcher::max_param_id) return false;
    id = static_cast<long>(v);
    return true;
}

} // namespace

const char* to_string(ProgramState s) {
    switch (s) {
    case ProgramState::idle: return "IDLE";
    case ProgramState::running: return "RUNNING";
    case ProgramState::halted: return "HALTED";
    case ProgramState::error: return "ERROR";
    }
    return "?";
}

Outcome Dispatcher::execute(const std::string& token, const std::string& data) {
    if (token == "EC") return echo(data);
    if (token == "ST") return state(data);
    if (token == "PR") return param_read(data);
    if (token == "PW") return param_write(data);
    if (token == "PU") return program_upload(data);
    if (token == "PD") return program_download(data);
    if (token == "TP") return teach_point(data);
    if (token == "TR") return teach_read(data);
    if (token == "RN") return run(data);
    if (token == "HT") return halt(data);
    if (token == "SP") return stop(data);
    if (token == "ES") return emergency_stop(data);
    if (is_motion_token(token)) return motion_command(token, data);
    return refuse(bch::unknown_token, "unknown token '" + token + "'");
}

Outcome Dispatcher::echo(const std::string& data) { return Outcome{bch::ok, data, ""}; }

// ST: robot state, program state, program name, then one position per axis, comma separated.
Outcome Dispatcher::state(const std::string& data) {
    if (!data.empty()) return refuse(bch::bad_data, "ST takes no data, got '" + data + "'");
    std::string out = motion_ ? motion_->state() : "NO_MOTION";
    out += ',';
    out += to_string(program_state());
    out += ',';
    out += current_program_;
    if (motion_)
        for (std::int64_t pos : motion_->positions()) out += ',' + std::to_string(pos);
    return Outcome{bch::ok, out, ""};
}

Outcome Dispatcher::param_read(const std::string& data) {
    long id = 0;
    if (!parse_param_id(data, id))
        return refuse(bch::bad_data, "PR id '" + data + "' is not an integer 0..65535");
    const auto it = parameters_.find(id);
    if (it == parameters_.end())
        return refuse(bch::bad_data, "PR parameter " + data + " was never written");
    return Outcome{bch::ok, std::to_string(it->second), ""};
}

Outcome Dispatcher::param_write(const std::string& data) {
    const auto f = split(data);
    long id = 0;
    std::int64_t value = 0;
    if (f.size() != 2) return refuse(bch::bad_data, "PW wants id,value, got '" + data + "'");
    if (!parse_param_id(f[0], id))
        return refuse(bch::bad_data, "PW id '" + f[0] + "' is not an integer 0..65535");
    if (!parse_int(f[1], value))
        return refuse(bch::bad_data, "PW value '" + f[1] + "' is not a decimal integer");
    parameters_[id] = value;
    return Outcome{};
}

// PU: the name is the first field; the program text is everything after the first comma (a
// program may contain commas itself).
Outcome Dispatcher::program_upload(const std::string& data) {
    const auto comma = data.find(',');
    if (comma == std::string::npos)
        return refuse(bch::bad_data, "PU wants name,program text, got no comma");
    const std::string name = data.substr(0, comma);
    if (!valid_name(name)) return refuse(bch::bad_data, "PU program name '" + name + "' is invalid");
    if (program_state() == ProgramState::running && current_program_ == name)
        return refuse(bch::busy, "PU: program '" + name + "' is running");
    programs_[name] = data.substr(comma + 1);
    return Outcome{};
}

Outcome Dispatcher::program_download(const std::string& data) {
    const auto it = programs_.find(data);
    if (it == programs_.end()) return refuse(bch::bad_data, "PD: no program named '" + data + "'");
    return Outcome{bch::ok, it->second, ""};
}

Outcome Dispatcher::teach_point(const std::string& data) {
    const auto f = split(data);
    if (f.size() != 5) return refuse(bch::bad_data, "TP wants name,x,y,z,r, got '" + data + "'");
    if (!valid_name(f[0])) return refuse(bch::bad_data, "TP point name '" + f[0] + "' is invalid");
    TeachPoint p;
    std::int64_t* coords[] = {&p.x, &p.y, &p.z, &p.r};
    for (int i = 0; i < 4; ++i)
        if (!parse_int(f[i + 1], *coords[i]))
            return refuse(bch::bad_data, "TP coordinate '" + f[i + 1] + "' is not a decimal integer");
    points_[f[0]] = p;
    return Outcome{};
}

Outcome Dispatcher::teach_read(const std::string& data) {
    const auto it = points_.find(data);
    if (it == points_.end()) return refuse(bch::bad_data, "TR: no teach point named '" + data + "'");
    const TeachPoint& p = it->second;
    return Outcome{bch::ok,
                   std::to_string(p.x) + ',' + std::to_string(p.y) + ',' + std::to_string(p.z) + ',' +
                       std::to_string(p.r),
                   ""};
}

ProgramState Dispatcher::program_state() const {
    if (!loaded_current_ || program_state_ != ProgramState::running) return program_state_;
    if (program_->running()) return ProgramState::running;
    return program_->error().empty() ? ProgramState::idle : ProgramState::error;
}

// RN of a PROGRAM of the loaded text starts it (cold: from its initial values); other names are
// the programs PU stored.
Outcome Dispatcher::run(const std::string& data) {
    if (program_ && program_->has_program(data)) return run_loaded(data);
    if (programs_.find(data) == programs_.end())
        return refuse(bch::bad_data, "RN: no program named '" + data + "'");
    if (program_state() == ProgramState::running)
        return refuse(bch::busy, "RN: program '" + current_program_ + "' is already running");
    program_state_ = ProgramState::running;
    current_program_ = data;
    loaded_current_ = false;
    return Outcome{};
}

Outcome Dispatcher::run_loaded(const std::string& name) {
    if (program_state() == ProgramState::running)
        return refuse(bch::busy, "RN: program '" + current_program_ + "' is already running");
    const std::string why = program_->start(name);
    if (!why.empty()) return refuse(bch::not_allowed, "RN: " + why);
    program_state_ = ProgramState::running;
    current_program_ = name;
    loaded_current_ = true;
    return Outcome{};
}

// SP ends the running program (IDLE; a loaded program's axes decelerate), HT halts it (HALTED).
Outcome Dispatcher::stop(const std::string& data) {
    if (!data.empty()) return refuse(bch::bad_data, "SP takes no data, got '" + data + "'");
    if (program_state() != ProgramState::running) return refuse(bch::not_allowed, "SP: no program is running");
    if (loaded_current_) program_->stop();
    program_state_ = ProgramState::idle;
    return Outcome{};
}

Outcome Dispatcher::halt(const std::string& data) {
    if (!data.empty()) return refuse(bch::bad_data, "HT takes no data, got '" + data + "'");
    if (program_state() != ProgramState::running)
        return refuse(bch::not_allowed, "HT: no program is running");
    if (loaded_current_) program_->stop();
    program_state_ = ProgramState::halted;
    return Outcome{};
}

// ES is never refused for its data: the program stops first, then the motion layer is told. With
// no motion layer the answer is 04, because the axes could not be stopped.
Outcome Dispatcher::emergency_stop(const std::string& data) {
    if (program_state() == ProgramState::running) {
        if (loaded_current_) program_->stop();
        program_state_ = ProgramState::halted;
    }
    if (!motion_)
        return refuse(bch::not_allowed, "ES: no motion interface, only the program was halted");
    const MotionReply r = motion_->command("ES", data);
    return Outcome{r.bch, r.data, r.bch == bch::ok ? "" : "ES: the motion layer answered " + proto::hex2(r.bch)};
}

Outcome Dispatcher::motion_command(const std::string& token, const std::string& data) {
    if (!motion_) return refuse(bch::not_allowed, token + ": no motion interface");
    const MotionReply r = motion_->command(token, data);
    return Outcome{r.bch, r.data, r.bch == bch::ok ? "" : token + ": the motion layer answered " + proto::hex2(r.bch)};
}

} // namespace rcsim
