// Helpers of the Structured Text tests: a program without axes, run cycle by cycle.
#pragma once

#include "main_cpu/st/program.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace rcsim::st::test {

/// Compiles `text` (file "t.st") with no axes and starts PROGRAM `name`.
inline std::unique_ptr<StProgram> started(const std::string& text, const std::string& name = "T",
                                          StProgram::Config cfg = {}) {
    auto p = std::make_unique<StProgram>(text, "t.st", std::vector<motion::McAxis*>{},
                                         std::vector<motion::MC_Power*>{}, cfg);
    const std::string why = p->start(name);
    EXPECT_EQ(why, "");
    return p;
}

/// PROGRAM T with these declarations (inside one VAR block) and this body, run once at t = 0.
inline std::unique_ptr<StProgram> run_body(const std::string& vars, const std::string& body) {
    auto p = started("PROGRAM T\nVAR\n" + vars + "\nEND_VAR\n" + body + "\nEND_PROGRAM\n");
    p->run_once(0);
    return p;
}

/// The compile error of `text` ("" if it compiles).
inline std::string compile_error(const std::string& text, const std::string& file = "t.st") {
    try {
        compile(text, file, 4);
    } catch (const CompileError& e) {
        return e.what();
    } catch (const std::exception& e) {
        return std::string("not a CompileError: ") + e.what();
    }
    return "";
}

} // namespace rcsim::st::test
