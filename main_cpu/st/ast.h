// rcsim — the compiled form of a Structured Text program: a typed tree of expressions and
// statements (every name resolved to a slot, every operand converted to its operator's type by
// the compiler), the POU types with their variable layouts, and the instances that hold the data.
//
// Execution walks the tree (ast.cpp). Every statement executed counts against the cycle's budget
// (ExecContext::budget); a runtime error throws RuntimeError naming the statement's position.
#pragma once

#include "main_cpu/st/types.h"

#include <functional>
#include <map>
#include <memory>
#include <vector>

namespace rcsim::motion {
class McAxis;
class MC_Power;
} // namespace rcsim::motion

namespace rcsim::st {

struct Instance;
struct ExecContext;

enum class VarKind : std::uint8_t { local, input, output, global, in_out };

/// One declared variable of a POU. Data live in Instance::vars from `slot` on (Type::slots() of
/// them); FB instances are Instance::fbs[slot]; a VAR_IN_OUT is Instance::refs[slot], the first
/// slot of the caller's variable it was given in this call.
struct VarInfo {
    std::string name; // as declared
    Type type;
    VarKind kind = VarKind::local;
    std::size_t slot = 0;
    SourcePos pos;
    std::vector<Value> init; // elementary/array: the initial value of each slot
    /// An FB instance (or each of an ARRAY OF one) declared with initial inputs: the instance's
    /// value slots, per element; an element without an entry (or an empty one) starts as declared.
    std::vector<std::vector<Value>> fb_init;
    bool read_only = false;  // the predefined axes, VAR CONSTANT
    bool constant = false;   // VAR CONSTANT: the compiler uses `init` in its place
};

/// A block written in C++ (TON, TOF, the MC_ blocks): called with its instance, whose input
/// slots the call has just set and whose output slots it fills.
class NativeBlock {
public:
    virtual ~NativeBlock() = default;
    virtual void call(Instance& self, ExecContext& ctx) = 0;
};

struct Stmt;
using StmtPtr = std::unique_ptr<Stmt>;
using Block = std::vector<StmtPtr>;

/// PROGRAM, FUNCTION_BLOCK or FUNCTION: its variables, its body (or a native implementation).
struct PouType {
    enum class Pou : std::uint8_t { program, function_block, function, globals } pou = Pou::function_block;
    std::string name;
    std::vector<VarInfo> vars;      // declaration order
    std::map<std::string, std::size_t> index; // upper-case name -> vars entry
    std::size_t value_slots = 0;
    std::size_t fb_slots = 0;
    std::size_t ref_slots = 0;      // VAR_IN_OUT
    std::size_t instances = 1;      // this one and every FB instance inside it, at any depth
    Block body;
    Type result;                    // FUNCTION: its type, in the variable named like the function
    std::function<std::unique_ptr<NativeBlock>()> native;

    const VarInfo* find(const std::string& upper_name) const {
        const auto it = index.find(upper_name);
        return it == index.end() ? nullptr : &vars[it->second];
    }
    std::unique_ptr<Instance> instantiate() const;
};

struct Instance {
    const PouType* type = nullptr;
    std::vector<Value> vars;
    std::vector<std::unique_ptr<Instance>> fbs;
    std::vector<Value*> refs; // VAR_IN_OUT: set by each call, used only during it
    std::unique_ptr<NativeBlock> native;
};

/// What a running statement sees.
struct ExecContext {
    Instance* self = nullptr;
    Instance* globals = nullptr;
    std::int64_t now_us = 0;               // the cycle's time, TIME microseconds
    std::vector<motion::McAxis*> axes;      // AXIS_REF n -> axes[n]
    /// The motion layer's own MC_Power of each axis (nullptr: none). The motion layer calls it
    /// every cycle, so an ST MC_Power drives that one instead of a second block on the axis.
    std::vector<motion::MC_Power*> power;
    std::uint64_t budget = 100000;          // statements per cycle
    std::uint64_t executed = 0;             // statements this cycle
    std::uint64_t motion_calls = 0;         // motion block calls this cycle (mc_blocks.cpp)

    /// Counts one statement; throws when the cycle's budget is spent.
    void tick(const SourcePos& at);
};

// ---- expressions ---------------------------------------------------------------------------------

struct Expr {
    Type type;
    SourcePos pos;
    virtual ~Expr() = default;
    virtual Value eval(ExecContext& c) const = 0;
    /// A STRING expression's characters (the other types are never asked).
    virtual std::string text(ExecContext&) const { return {}; }
    /// A literal (or an expression of literals, folded): its value is known to the compiler.
    virtual bool constant() const { return false; }
};
using ExprPtr = std::unique_ptr<Expr>;

struct Const : Expr {
    Value v;
    std::string s; // a STRING literal's characters
    bool untyped_int = false, untyped_real = false; // ANY_INT / ANY_REAL literal: adapts to its use
    Value eval(ExecContext&) const override { return v; }
    std::string text(ExecContext&) const override { return s; }
    bool constant() const override { return true; }
};

/// Where an FB instance is: in the running POU's instance or in the globals; for an element of
/// an ARRAY OF a block, `slot` is the first element's and `index` (checked against lo..hi when
/// it runs, like any array index) picks one.
struct InstancePath {
    bool global = false;
    std::size_t slot = 0;
    std::shared_ptr<const Expr> index; // shared: an LValue's path is copied per member read
    std::int64_t lo = 0, hi = 0;
    SourcePos pos;
    std::string name; // the array's, for the error
    Instance* get(ExecContext& c) const;
};

/// A variable that can be read and written: the slots of an instance (the running POU's, the
/// globals', an FB instance's member, or those a VAR_IN_OUT refers to), a fixed offset (STRUCT
/// members) and the array indices, each checked against its bounds.
struct LValue : Expr {
    enum class Base : std::uint8_t { self, global, fb_member, in_out };
    Base base = Base::self;
    InstancePath inst;    // Base::fb_member: the instance
    std::size_t slot = 0; // the variable's first slot (Base::in_out: its refs entry)
    std::size_t offset = 0;
    struct Index {
        ExprPtr index;
        std::int64_t lo = 0, hi = 0;
        std::size_t stride = 1;
    };
    std::vector<Index> indices;
    bool read_only = false;
    std::string name;

    /// The first slot of the datum.
    Value* first(ExecContext& c) const;
    Value& ref(ExecContext& c) const { return *first(c); }
    Value eval(ExecContext& c) const override { return *first(c); }
    std::string text(ExecContext& c) const override { return unpack(first(c)); }
};
using LValuePtr = std::unique_ptr<LValue>;

/// Stores `e` (of a type assignable to `t`) in the slots from `dst`: one value, a STRING (cut to
/// t.len characters), or a STRUCT or ARRAY copied slot by slot from the variable `e` names.
void store(Value* dst, const Type& t, const Expr& e, ExecContext& c);
/// Copies a datum of type `from` at `src` into one of type `to` (equal, or both STRINGs).
void copy_datum(Value* dst, const Type& to, const Value* src, const Type& from);

enum class Op : std::uint8_t { add, sub, mul, div, mod, pow, lt, le, gt, ge, eq, ne, and_, or_, xor_, neg, not_ };

struct Unary : Expr {
    Op op = Op::neg;
    ExprPtr a;
    Value eval(ExecContext& c) const override;
};

/// A binary operator. `a` and `b` have the operand type `operand` (the compiler converted them);
/// `type` is the result (BOOL for comparisons, TIME for TIME * number).
struct Binary : Expr {
    Op op = Op::add;
    Type operand;
    ExprPtr a, b;
    Value eval(ExecContext& c) const override;
};

/// An implicit widening (INT -> DINT, DINT -> LREAL, ...) or an explicit X_TO_Y conversion.
struct Convert : Expr {
    ExprPtr a;
    bool truncate = false; // TRUNC: towards zero; conversions round to nearest
    Value eval(ExecContext& c) const override;
};

/// A comparison of two STRINGs (character codes, as IEC 61131-3 §6.6.2.5.11 orders them).
struct StringCompare : Expr {
    Op op = Op::eq;
    ExprPtr a, b;
    Value eval(ExecContext& c) const override;
};

/// A STRING function (CONCAT, LEFT, RIGHT, MID, INSERT, DELETE, ...): a C++ function of the
/// arguments' texts and integers; the result cut to `type.len`.
struct StringFn : Expr {
    std::vector<ExprPtr> args;
    std::string (*fn)(const std::vector<std::string>& s, const std::vector<std::int64_t>& n, const SourcePos& at) =
        nullptr;
    Value eval(ExecContext&) const override { return {}; }
    std::string text(ExecContext& c) const override;
};

/// LEN, FIND: an integer of STRING arguments.
struct StringInt : Expr {
    std::vector<ExprPtr> args;
    std::int64_t (*fn)(const std::vector<std::string>& s) = nullptr;
    Value eval(ExecContext& c) const override;
};

/// SEL(G, IN0, IN1) and MUX(K, IN0, ..., INn) (IEC 61131-3 Table 32): only the chosen input is
/// evaluated. K outside 0..n is a runtime error (the standard calls it an error; nothing to pick).
struct Select : Expr {
    bool mux = false;
    ExprPtr selector;
    std::vector<ExprPtr> inputs;
    const Expr& chosen(ExecContext& c) const;
    Value eval(ExecContext& c) const override { return chosen(c).eval(c); }
    std::string text(ExecContext& c) const override { return chosen(c).text(c); }
};

/// ABS, SQRT, MIN, MAX, LIMIT, SIN, COS, SHL, ROL, ...: a C++ function of the evaluated arguments.
struct Builtin : Expr {
    std::string fname;
    std::vector<ExprPtr> args;
    Value (*fn)(const Type& t, const std::vector<Value>& a, const SourcePos& at) = nullptr;
    Value eval(ExecContext& c) const override;
};

/// A user FUNCTION: a fresh instance per call, the inputs set, the body run, the result read.
struct FunctionCall : Expr {
    const PouType* fn = nullptr;
    std::vector<std::pair<const VarInfo*, ExprPtr>> inputs; // the input, its value
    std::vector<std::pair<std::size_t, LValuePtr>> in_outs; // refs entry, the variable
    std::size_t result_slot = 0;
    Value eval(ExecContext& c) const override;
};

// ---- statements ----------------------------------------------------------------------------------

enum class Flow : std::uint8_t { normal, exit, cont, ret };

struct Stmt {
    SourcePos pos;
    virtual ~Stmt() = default;
    virtual Flow exec(ExecContext& c) const = 0;
};

Flow run_block(const Block& b, ExecContext& c);

struct Assign : Stmt {
    LValuePtr target;
    ExprPtr value;
    Flow exec(ExecContext& c) const override;
};

/// inst(In := x, Out => y): inputs set (in the caller's context), the body run in the
/// instance's, then the outputs copied out.
struct FbCall : Stmt {
    InstancePath inst;
    std::vector<std::pair<const VarInfo*, ExprPtr>> inputs;     // the input, its value
    std::vector<std::pair<const VarInfo*, LValuePtr>> outputs;  // the output, its destination
    std::vector<std::pair<std::size_t, LValuePtr>> in_outs;     // refs entry, the variable
    Flow exec(ExecContext& c) const override;
};

struct If : Stmt {
    std::vector<std::pair<ExprPtr, Block>> branches;
    Block otherwise;
    Flow exec(ExecContext& c) const override;
};

struct Case : Stmt {
    struct Element {
        std::vector<std::pair<std::int64_t, std::int64_t>> ranges;
        Block body;
    };
    ExprPtr selector;
    std::vector<Element> elements;
    Block otherwise;
    Flow exec(ExecContext& c) const override;
};

struct For : Stmt {
    LValuePtr var;
    ExprPtr from, to, by;
    Block body;
    Flow exec(ExecContext& c) const override;
};

struct While : Stmt {
    ExprPtr cond;
    Block body;
    Flow exec(ExecContext& c) const override;
};

struct Repeat : Stmt {
    Block body;
    ExprPtr until;
    Flow exec(ExecContext& c) const override;
};

struct Exit : Stmt {
    Flow exec(ExecContext& c) const override;
};

struct Continue : Stmt {
    Flow exec(ExecContext&) const override { return Flow::cont; }
};

struct Return : Stmt {
    Flow exec(ExecContext& c) const override;
};

/// Runs a POU body (or its native block) in `inst`.
void run_pou(Instance& inst, ExecContext& c);

} // namespace rcsim::st
