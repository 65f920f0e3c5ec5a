// rcsim — exit codes and the one-line message for a run that could not complete.
//
// 0 every check holds, 1 a check failed, 2 bad input (the message names the file and line or the
// offending value), 3 internal error (a model reported an error no input explains: the message
// names the model and the simulated time), 128 + N ended by signal N (130 SIGINT, 143 SIGTERM).
// docs/scenarios.md "Exit codes" is the reference; `rcsim --help` repeats it.
#pragma once

#include <string>

namespace rcsim {

constexpr int kExitPassed = 0;
constexpr int kExitCheckFailed = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitInternal = 3;

/// The text `rcsim --help` shows.
extern const char* const kExitCodesHelp;

/// Call inside a catch block: prints "PREFIX: message" for the exception in flight to stderr (one
/// line, control characters escaped) and returns its exit code. A ConfigError is bad input; an
/// exhausted memory (std::bad_alloc) is bad input naming `input` (the scenario or file the
/// command was given); a SystemC error report or any other exception is an internal error, or
/// "unsupported by the model" when its message type ends in "/unsupported" (legal hardware
/// behaviour a model does not implement, such as a cascaded 8259A).
int report_exception(const std::string& prefix, const std::string& input);

/// `text` on one line: control characters (newlines too) as \xNN.
std::string one_line(const std::string& text);

/// The exit code a subcommand's callback ends with, for main() to return after the command line
/// was parsed. Handed over without an exception: in a sanitizer build ASan warns on stderr at the
/// first throw on the main thread after sc_start() (tests/scenarios/cli/CMakeLists.txt).
void set_command_exit_code(int code);
int command_exit_code();

} // namespace rcsim
