// A scenario file's bad input as a test sees it: the message of the ConfigError load_scenario()
// throws (it names the file, the line and the key or value).
#pragma once

#include "models/plumbing/config_error.h"
#include "scenarios/config/scenario.h"
#include "tests/support/files.h"

#include <fstream>
#include <functional>
#include <string>

namespace rcsim::test {

/// The message of the ConfigError `f` throws, or "" when it throws none.
inline std::string config_error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

/// The message load_scenario(path) throws, or "(no error)" when the scenario loads.
inline std::string scenario_error(const std::string& path) {
    try {
        load_scenario(path);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "(no error)";
}

/// The same for a scenario of `text`, written to scratch_dir()/name (the message names it).
inline std::string scenario_error_of(const std::string& name, const std::string& text) {
    const std::string path = (scratch_dir() / name).string();
    std::ofstream(path) << text;
    return scenario_error(path);
}

} // namespace rcsim::test
