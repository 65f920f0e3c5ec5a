#include "scenarios/run/failure.h"

#include "models/plumbing/config_error.h"

#include <systemc>

#include <cstdio>
#include <iostream>
#include <new>
#include <sstream>

namespace rcsim {

const char* const kExitCodesHelp =
    "Exit codes: 0 PASSED, every check holds; 1 FAILED, a check failed; 4 INCONCLUSIVE, none failed\n"
    "but one was not measured; 2 bad input (the message names the file and line or the value);\n"
    "3 internal error (a model error no input explains: the message names the model and the\n"
    "simulated time); 130 / 143 INTERRUPTED by SIGINT / SIGTERM (reports say interrupted).";

std::string one_line(const std::string& text) {
    std::string out;
    for (const char c : text) {
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x20 && u != 0x7F) {
            out += c;
            continue;
        }
        char hex[5];
        std::snprintf(hex, sizeof hex, "\\x%02X", u);
        out += hex;
    }
    return out;
}

namespace {

/// "rcsim/pic8259 in world.controller.comm.cpu at 1.234 ms: <message>". SystemC turns an
/// exception thrown inside a process into a report of its own type; its message is the
/// exception's text.
std::string describe(const sc_core::sc_report& r) {
    std::ostringstream os;
    os << r.get_msg_type();
    const std::string process = r.get_process_name() ? r.get_process_name() : "";
    if (!process.empty()) os << " in " << process;
    os << " at " << r.get_time().to_string() << ": " << r.get_msg();
    return os.str();
}

} // namespace

int report_exception(const std::string& prefix, const std::string& input) {
    std::string message;
    int code = kExitInternal;
    try {
        throw;
    } catch (const ConfigError& e) {
        message = e.what();
        code = kExitBadInput;
    } catch (const std::bad_alloc&) {
        message = input + ": out of memory: the input asks for more than this machine has";
        code = kExitBadInput;
    } catch (const sc_core::sc_report& r) {
        // SystemC turns an exception thrown inside a process into a report of its own ("uncaught
        // exception") carrying the exception's text; memory exhausted there is the input's doing.
        if (std::string(r.get_msg_type()) == sc_core::SC_ID_SIMULATION_UNCAUGHT_EXCEPTION_ &&
            std::string(r.get_msg()) == "std::bad_alloc") {
            std::cerr << prefix << ": " << one_line(input + ": out of memory at " + r.get_time().to_string() +
                                                    ": the input asks for more than this machine has")
                      << "\n";
            return kExitBadInput;
        }
        // Models report legal hardware behaviour they do not implement under ".../unsupported".
        const std::string type = r.get_msg_type();
        const std::string tail = "/unsupported";
        const bool unsupported = type.size() > tail.size() && type.compare(type.size() - tail.size(), tail.size(), tail) == 0;
        message = (unsupported ? "unsupported by the model: " : "internal error: ") + describe(r);
    } catch (const std::exception& e) {
        message = std::string("internal error: ") + e.what();
    } catch (...) {
        message = "internal error: an unknown exception";
    }
    std::cerr << prefix << ": " << one_line(message) << "\n";
    return code;
}

namespace {
int g_command_exit_code = kExitPassed;
} // namespace

void set_command_exit_code(int code) { g_command_exit_code = code; }
int command_exit_code() { return g_command_exit_code; }

} // namespace rcsim
