// rcsim — the Structured Text subset's data types and values (docs/st.md "Data types").
//
// Every variable is one or more Value slots; the static type (Type) says which field holds what:
// BOOL, the integers, TIME (microseconds) and AXIS_REF (the axis number, -1 = none) in `i`; REAL
// and LREAL in `r` (REAL rounded to float precision on every store, as a 32-bit variable would be).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace rcsim::st {

/// A parse or type error: "file:line:column: what was expected or is wrong".
class CompileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// An error while the program runs (division by zero, array bounds, the statement budget):
/// "file:line:column: what happened". The program stops; the axes go to ErrorStop.
class RuntimeError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct SourcePos {
    std::string_view file;
    std::size_t line = 0, column = 0;
    std::string str() const { return std::string(file) + ":" + std::to_string(line) + ":" + std::to_string(column); }
};

enum class Kind : std::uint8_t { Void, Bool, Int, Dint, Udint, Real, Lreal, Time, AxisRef, Fb, Array };

struct PouType;

struct Type {
    Kind kind = Kind::Void;
    const PouType* fb = nullptr; // Kind::Fb: the function block type
    Kind elem = Kind::Void;      // Kind::Array: the element type (elementary)
    std::int64_t lo = 0, hi = -1; // Kind::Array: the index range

    static Type of(Kind k) { return Type{k}; }
    bool is(Kind k) const { return kind == k; }
    bool integer() const { return kind == Kind::Int || kind == Kind::Dint || kind == Kind::Udint; }
    bool real() const { return kind == Kind::Real || kind == Kind::Lreal; }
    bool numeric() const { return integer() || real(); }
    bool elementary() const { return kind != Kind::Void && kind != Kind::Fb && kind != Kind::Array; }
    std::size_t slots() const { return kind == Kind::Array ? static_cast<std::size_t>(hi - lo + 1) : 1; }
    std::string name() const;
    bool operator==(const Type& o) const {
        return kind == o.kind && fb == o.fb && elem == o.elem && lo == o.lo && hi == o.hi;
    }
    bool operator!=(const Type& o) const { return !(*this == o); }
};

const char* kind_name(Kind k);

struct Value {
    std::int64_t i = 0;
    double r = 0;
};

/// Two's complement wrap of an integer result to the width of `k` (IEC 61131-3 leaves overflow
/// to the implementation; this is what a 16/32-bit PLC register does). TIME is 64-bit.
std::int64_t wrap(Kind k, std::int64_t v);
/// A value converted to a store of kind `k` (REAL rounded to float, integers wrapped).
Value normalise(Kind k, Value v);

} // namespace rcsim::st
