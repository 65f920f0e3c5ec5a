// rcsim — a function run in a child process, its result back through a pipe.
//
// SystemC elaborates once per process, and two boards in one kernel would bound each other's CPU
// slices: a board run that is measured (`rcsim bench system`) or compared with another (a speed-up
// switched on and off, in the tests) runs in a child of its own. Plain C++: no SystemC here.
#pragma once

#include <functional>
#include <optional>
#include <string>

namespace rcsim {

/// Runs `body` in a forked child and returns the bytes it returned; nullopt when the child
/// failed: it threw (the message goes to stderr after `who`), could not send every byte, crashed
/// or exited otherwise than with 0.
std::optional<std::string> run_in_child_process(const std::function<std::string()>& body, const std::string& who);

} // namespace rcsim
