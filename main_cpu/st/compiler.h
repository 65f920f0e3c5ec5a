// rcsim — the Structured Text compiler: parse trees (parser.h) to the typed tree of ast.h.
//
// Names are resolved (the POU's own variables first, then VAR_GLOBAL and the predefined axes
// Axis0..Axis3), every operand gets its operator's type under IEC 61131-3's implicit widening
// rules (INT -> DINT -> LREAL, INT -> REAL -> LREAL, UDINT -> LREAL; untyped literals take the
// type their use needs), and constant expressions are folded. Unknown identifiers, type
// mismatches and misplaced statements are CompileErrors naming file:line:column.
#pragma once

#include "main_cpu/st/ast.h"

#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rcsim::st {

/// A compiled program text with the standard and motion blocks it can use.
struct Unit {
    std::deque<std::string> texts, files; // the sources (the tree's positions point into these)
    std::vector<std::unique_ptr<PouType>> pous;
    std::vector<std::unique_ptr<EnumType>> enums;     // TYPE ... END_TYPE
    std::vector<std::unique_ptr<StructType>> structs;
    PouType globals;
    std::map<std::string, const PouType*> programs; // upper-case name -> PROGRAM
    std::vector<std::string> program_names;          // as declared, in order

    const PouType* type(const std::string& upper_name) const;
};

/// Compiles `text` (file name `file`, for the messages) together with the standard library.
/// `axes`: how many AXIS_REF constants Axis0.. to predefine. Throws CompileError.
std::unique_ptr<Unit> compile(const std::string& text, const std::string& file, unsigned axes = 4);

/// Upper-case ASCII (ST names are case-insensitive).
std::string upper(std::string s);

} // namespace rcsim::st
