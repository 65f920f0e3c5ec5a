// rcsim — the Structured Text subset's data types and values (docs/st.md "Data types").
//
// Every variable is one or more Value slots; the static type (Type) says which field holds what:
// BOOL, the integers, the bit strings BYTE/WORD/DWORD (unsigned), TIME (microseconds), an
// enumeration's value and AXIS_REF (the axis number, -1 = none) in `i`; REAL and LREAL in `r`
// (REAL rounded to float precision on every store, as a 32-bit variable would be). A STRING[n] is
// its length in the first slot's `i` and its characters packed 8 to a slot after it; a STRUCT is
// its members' slots one after the other; an ARRAY its elements'. So every datum, however
// composite, is a run of slots that a VAR_IN_OUT can point at and an assignment can copy.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

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

enum class Kind : std::uint8_t {
    Void, Bool, Int, Dint, Udint, Real, Lreal, Time, AxisRef, Fb, Array, Byte, Word, Dword, String, Enum, Struct
};

struct Value {
    std::int64_t i = 0;
    double r = 0;
};

struct PouType;
struct EnumType;
struct StructType;

struct Type {
    Kind kind = Kind::Void;
    const PouType* fb = nullptr; // Kind::Fb: the function block type (or an array of one)
    Kind elem = Kind::Void;      // Kind::Array: the element's kind (described by en, st, len below)
    std::int64_t lo = 0, hi = -1; // Kind::Array: the index range
    const EnumType* en = nullptr;   // Kind::Enum (or an array of one)
    const StructType* st = nullptr; // Kind::Struct (or an array of one)
    std::int64_t len = 0;           // Kind::String: the most characters (or an array of strings)

    static Type of(Kind k) { return Type{k}; }
    bool is(Kind k) const { return kind == k; }
    bool integer() const { return kind == Kind::Int || kind == Kind::Dint || kind == Kind::Udint; }
    bool real() const { return kind == Kind::Real || kind == Kind::Lreal; }
    bool numeric() const { return integer() || real(); }
    /// BYTE, WORD, DWORD (ANY_BIT without BOOL).
    bool bits() const { return kind == Kind::Byte || kind == Kind::Word || kind == Kind::Dword; }
    /// A single-slot value an expression can compute (not a STRING, a STRUCT, an ARRAY, an FB).
    bool elementary() const {
        return kind != Kind::Void && kind != Kind::Fb && kind != Kind::Array && kind != Kind::String &&
               kind != Kind::Struct;
    }
    /// ARRAY[..] OF a function block: its instances are fb slots, not value slots.
    bool fb_array() const { return kind == Kind::Array && elem == Kind::Fb; }
    /// What an ARRAY holds.
    Type element() const {
        Type e{elem};
        e.fb = fb;
        e.en = en;
        e.st = st;
        e.len = len;
        return e;
    }
    std::size_t slots() const;
    std::string name() const;
    bool operator==(const Type& o) const {
        return kind == o.kind && fb == o.fb && elem == o.elem && lo == o.lo && hi == o.hi && en == o.en &&
               st == o.st && len == o.len;
    }
    bool operator!=(const Type& o) const { return !(*this == o); }
};

/// TYPE Name : (A, B := 5, C); END_TYPE — the values in order (IEC 61131-3 §6.4.4.2: without
/// a given value, one more than the one before, the first 0).
struct EnumType {
    std::string name;
    std::vector<std::pair<std::string, std::int64_t>> values;
    std::int64_t init = 0; // the first value unless the declaration gives one
    /// The name of value v ("" if none has it).
    std::string value_name(std::int64_t v) const;
};

/// TYPE Name : STRUCT ... END_STRUCT; END_TYPE — the members' slots one after the other.
struct StructType {
    struct Member {
        std::string name;
        Type type;
        std::size_t offset = 0;
    };
    std::string name;
    std::vector<Member> members;
    std::vector<Value> init; // of every slot
    std::size_t slots = 0;
    const Member* find(const std::string& upper_name) const;
};

const char* kind_name(Kind k);


/// Two's complement wrap of an integer result to the width of `k` (IEC 61131-3 leaves overflow
/// to the implementation; this is what a 16/32-bit PLC register does). TIME is 64-bit.
std::int64_t wrap(Kind k, std::int64_t v);
/// A value converted to a store of kind `k` (REAL rounded to float, integers wrapped).
Value normalise(Kind k, Value v);

/// A STRING's slots: slots_for(n) hold n characters; pack() stores at most n (the rest cut, as
/// IEC 61131-3 §6.4.2 truncates an assignment to a shorter string), unpack() reads them back.
std::size_t string_slots(std::int64_t n);
void pack(Value* slots, std::int64_t n, const std::string& text);
std::string unpack(const Value* slots);

} // namespace rcsim::st
