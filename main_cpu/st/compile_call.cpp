// rcsim — the Structured Text compiler: calls of functions (user FUNCTIONs, the standard
// functions of docs/st.md, the X_TO_Y conversions) in expressions. See compiler.h.
#include "main_cpu/st/compiler_impl.h"
#include "main_cpu/st/grammar.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <utility>

namespace rcsim::st::detail {

namespace g = grammar;

namespace {

/// TIME(): the time of the current control cycle (CODESYS's TIME() operator).
struct Now : Expr {
    Value eval(ExecContext& c) const override { return Value{c.now_us, 0}; }
};

Value fn_abs(const Type& t, const std::vector<Value>& a, const SourcePos&) {
    Value v = a[0];
    if (t.real()) v.r = std::fabs(v.r);
    else if (v.i < 0) v.i = static_cast<std::int64_t>(0 - static_cast<std::uint64_t>(v.i));
    return v;
}

bool less(const Type& t, const Value& x, const Value& y) { return t.real() ? x.r < y.r : x.i < y.i; }

Value fn_min(const Type& t, const std::vector<Value>& a, const SourcePos&) {
    Value m = a[0];
    for (const Value& v : a)
        if (less(t, v, m)) m = v;
    return m;
}

Value fn_max(const Type& t, const std::vector<Value>& a, const SourcePos&) {
    Value m = a[0];
    for (const Value& v : a)
        if (less(t, m, v)) m = v;
    return m;
}

Value fn_limit(const Type& t, const std::vector<Value>& a, const SourcePos&) { // LIMIT(MN, IN, MX)
    if (less(t, a[1], a[0])) return a[0];
    if (less(t, a[2], a[1])) return a[2];
    return a[1];
}

/// The REAL functions of IEC 61131-3 Table 22 (and EXPT of Table 24): each evaluates in double
/// and stops the program where the result is not a finite real (LN(0), ASIN(2), EXPT(-8.0, 0.5)),
/// as SQRT of a negative number always did, instead of carrying a NaN into a set-point.
struct RealFunction {
    const char* name;
    unsigned arity;
    double (*one)(double);         // arity 1
    double (*two)(double, double); // arity 2: ATAN2(Y, X), EXPT(IN1, IN2)
};
double sqrt_(double x) { return std::sqrt(x); }
constexpr std::size_t kSqrt = 0; // its own message, as before the table
constexpr RealFunction kRealFunctions[] = {
    {"SQRT", 1, sqrt_, nullptr},
    {"LN", 1, [](double x) { return std::log(x); }, nullptr},
    {"LOG", 1, [](double x) { return std::log10(x); }, nullptr},
    {"EXP", 1, [](double x) { return std::exp(x); }, nullptr},
    {"SIN", 1, [](double x) { return std::sin(x); }, nullptr},
    {"COS", 1, [](double x) { return std::cos(x); }, nullptr},
    {"TAN", 1, [](double x) { return std::tan(x); }, nullptr},
    {"ASIN", 1, [](double x) { return std::asin(x); }, nullptr},
    {"ACOS", 1, [](double x) { return std::acos(x); }, nullptr},
    {"ATAN", 1, [](double x) { return std::atan(x); }, nullptr},
    {"ATAN2", 2, nullptr, [](double y, double x) { return std::atan2(y, x); }},
    {"EXPT", 2, nullptr, [](double b, double e) { return std::pow(b, e); }},
};

std::string real_text(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

template <std::size_t I> Value real_fn(const Type&, const std::vector<Value>& a, const SourcePos& at) {
    const RealFunction& f = kRealFunctions[I];
    if (I == kSqrt && a[0].r < 0) throw RuntimeError(at.str() + ": SQRT of the negative number " + std::to_string(a[0].r));
    const double r = f.arity == 1 ? f.one(a[0].r) : f.two(a[0].r, a[1].r);
    if (!std::isfinite(r))
        throw RuntimeError(at.str() + ": " + f.name + "(" + real_text(a[0].r) + (f.arity == 2 ? ", " + real_text(a[1].r) : "") +
                           ") has no finite real result");
    return Value{0, r};
}

using BuiltinFn = Value (*)(const Type&, const std::vector<Value>&, const SourcePos&);
template <std::size_t... I> constexpr std::array<BuiltinFn, sizeof...(I)> real_fns(std::index_sequence<I...>) {
    return {real_fn<I>...};
}
constexpr auto kRealFns = real_fns(std::make_index_sequence<std::size(kRealFunctions)>());

/// The index of NAME in kRealFunctions, or -1.
int real_function(const std::string& name) {
    for (std::size_t i = 0; i < std::size(kRealFunctions); ++i)
        if (name == kRealFunctions[i].name) return static_cast<int>(i);
    return -1;
}

/// SHL, SHR, ROL, ROR (IEC 61131-3 Table 29) on the width of IN's type: SHL on a WORD drops the
/// bits shifted past bit 15, ROL on a WORD brings bit 15 round to bit 0.
template <int Which> Value fn_shift(const Type& t, const std::vector<Value>& a, const SourcePos& at) {
    const unsigned w = t.kind == Kind::Byte ? 8 : t.kind == Kind::Word ? 16 : 32;
    const std::uint64_t mask = (std::uint64_t{1} << w) - 1, x = static_cast<std::uint64_t>(a[0].i) & mask;
    const std::int64_t n = a[1].i;
    if (n < 0) throw RuntimeError(at.str() + ": a negative shift count N = " + std::to_string(n));
    const unsigned r = static_cast<unsigned>(n % w);
    std::uint64_t v = 0;
    switch (Which) {
    case 0: v = n >= static_cast<std::int64_t>(w) ? 0 : (x << n) & mask; break;                 // SHL
    case 1: v = n >= static_cast<std::int64_t>(w) ? 0 : x >> n; break;                           // SHR
    case 2: v = r == 0 ? x : ((x << r) | (x >> (w - r))) & mask; break;                          // ROL
    default: v = r == 0 ? x : ((x >> r) | (x << (w - r))) & mask; break;                         // ROR
    }
    return Value{static_cast<std::int64_t>(v), 0};
}

// The character string functions (Table 43), positions counted from 1.
std::int64_t fn_len(const std::vector<std::string>& s) { return static_cast<std::int64_t>(s[0].size()); }
std::int64_t fn_find(const std::vector<std::string>& s) {
    const auto p = s[0].find(s[1]);
    return p == std::string::npos || s[1].empty() ? 0 : static_cast<std::int64_t>(p) + 1;
}
std::size_t count_arg(std::int64_t n, const char* what, const SourcePos& at) {
    if (n < 0) throw RuntimeError(at.str() + ": " + what + " = " + std::to_string(n) + " is negative");
    return static_cast<std::size_t>(n);
}
std::string fn_concat(const std::vector<std::string>& s, const std::vector<std::int64_t>&, const SourcePos&) {
    std::string out;
    for (const std::string& x : s) out += x;
    return out;
}
std::string fn_left(const std::vector<std::string>& s, const std::vector<std::int64_t>& n, const SourcePos& at) {
    return s[0].substr(0, count_arg(n[0], "L", at));
}
std::string fn_right(const std::vector<std::string>& s, const std::vector<std::int64_t>& n, const SourcePos& at) {
    const std::size_t l = std::min(count_arg(n[0], "L", at), s[0].size());
    return s[0].substr(s[0].size() - l);
}
std::string fn_mid(const std::vector<std::string>& s, const std::vector<std::int64_t>& n, const SourcePos& at) {
    // MID(IN, L, P): L characters from the P-th; P from 1 to LEN(IN) + 1.
    const std::size_t l = count_arg(n[0], "L", at), p = count_arg(n[1], "P", at);
    if (p < 1 || p > s[0].size() + 1)
        throw RuntimeError(at.str() + ": MID position P = " + std::to_string(p) + " outside 1.." +
                           std::to_string(s[0].size() + 1));
    return s[0].substr(p - 1, l);
}

std::size_t position(std::int64_t p, const std::string& in, const char* fn, const SourcePos& at) {
    if (p < 1 || p > static_cast<std::int64_t>(in.size()) + 1)
        throw RuntimeError(at.str() + ": " + fn + " position P = " + std::to_string(p) + " outside 1.." +
                           std::to_string(in.size() + 1));
    return static_cast<std::size_t>(p);
}
std::string fn_insert(const std::vector<std::string>& s, const std::vector<std::int64_t>& n, const SourcePos& at) {
    // INSERT(IN1, IN2, P): IN2 after the P-th character of IN1 (P = 0 puts it first).
    if (n[0] < 0 || n[0] > static_cast<std::int64_t>(s[0].size()))
        throw RuntimeError(at.str() + ": INSERT position P = " + std::to_string(n[0]) + " outside 0.." +
                           std::to_string(s[0].size()));
    return std::string(s[0]).insert(static_cast<std::size_t>(n[0]), s[1]);
}
std::string fn_delete(const std::vector<std::string>& s, const std::vector<std::int64_t>& n, const SourcePos& at) {
    // DELETE(IN, L, P): L characters from the P-th removed.
    const std::size_t l = count_arg(n[0], "L", at), p = position(n[1], s[0], "DELETE", at);
    return std::string(s[0]).erase(p - 1, l);
}
std::string fn_replace(const std::vector<std::string>& s, const std::vector<std::int64_t>& n, const SourcePos& at) {
    // REPLACE(IN1, IN2, L, P): L characters of IN1 from the P-th replaced by IN2.
    const std::size_t l = count_arg(n[0], "L", at), p = position(n[1], s[0], "REPLACE", at);
    return std::string(s[0]).replace(p - 1, l, s[1]);
}

} // namespace

Type Compiler::common_of(const std::vector<ExprPtr>& args, std::size_t from, const std::string& name,
                         const ParseNode& n) {
    // The typed arguments' common type; the literals take it. Literals only: the smallest type
    // that holds them all (an INT widens where it is used).
    struct Probe : Expr {
        Value eval(ExecContext&) const override { return {}; }
    } probe;
    bool typed = false;
    for (std::size_t i = from; i < args.size(); ++i) {
        if (untyped(*args[i])) continue;
        probe.type = typed ? common_type(probe, *args[i], name, n) : args[i]->type;
        typed = true;
    }
    if (typed) return probe.type;
    Type t = Type::of(Kind::Int);
    for (std::size_t i = from; i < args.size(); ++i) {
        const auto& c = dynamic_cast<const Const&>(*args[i]);
        if (c.untyped_real) t = Type::of(Kind::Lreal);
        else if (t.kind == Kind::Int && !fits(Kind::Int, c.v.i)) t = Type::of(Kind::Dint);
    }
    return t;
}

ExprPtr Compiler::conversion(Kind from, Kind to, std::vector<ExprPtr> args, const ParseNode& n, bool truncate) {
    const std::string name = trim(n.children.at(0)->string());
    if (args.size() != 1) fail(n, name + " takes one argument, not " + std::to_string(args.size()));
    auto c = std::make_unique<Convert>();
    c->pos = at(n);
    c->type = Type::of(to);
    c->truncate = truncate;
    c->a = coerce(std::move(args[0]), Type::of(from), "the argument of " + name);
    const bool k = c->a->constant();
    return k ? fold(std::move(c)) : std::move(c);
}

ExprPtr Compiler::builtin(const std::string& name, std::vector<ExprPtr> args, const ParseNode& n) {
    auto b = std::make_unique<Builtin>();
    b->pos = at(n);
    b->fname = name;
    bool lit_int = !args.empty(), lit_real = false; // all arguments literals: see the end
    for (const ExprPtr& a : args) {
        const auto* c = dynamic_cast<const Const*>(a.get());
        lit_int = lit_int && c && (c->untyped_int || c->untyped_real);
        lit_real = lit_real || (c && c->untyped_real);
    }
    const bool all_int = lit_int && !lit_real;
    auto count = [&](std::size_t lo, std::size_t hi) {
        if (args.size() < lo || args.size() > hi)
            fail(n, name + " takes " + (lo == hi ? std::to_string(lo) : std::to_string(lo) + " or more") +
                        " argument" + (hi == 1 ? "" : "s") + ", not " + std::to_string(args.size()));
    };
    if (name == "ABS") {
        count(1, 1);
        if (!args[0]->type.numeric()) fail(n, "type mismatch: ABS needs a number, not " + args[0]->type.name());
        b->type = args[0]->type;
        b->fn = fn_abs;
    } else if (const int r = real_function(name); r >= 0) {
        // One type for the arguments and the result: REAL when every typed argument is a REAL,
        // else LREAL (EXPT's exponent may be any number: it is converted as the base is).
        const unsigned arity = kRealFunctions[r].arity;
        count(arity, arity);
        bool real = false, lreal = false;
        for (const ExprPtr& a : args) {
            if (!untyped(*a) && !a->type.numeric())
                fail(n, "type mismatch: " + name + " needs numbers, not " + a->type.name());
            real = real || a->type.kind == Kind::Real;
            lreal = lreal || (!untyped(*a) && a->type.kind != Kind::Real);
        }
        b->type = real && !lreal ? Type::of(Kind::Real) : Type::of(Kind::Lreal);
        for (ExprPtr& a : args) a = coerce(std::move(a), b->type, "an argument of " + name);
        b->fn = kRealFns[static_cast<std::size_t>(r)];
    } else {
        // MIN, MAX (two or more), LIMIT(MN, IN, MX): one common type for all arguments.
        if (name == "LIMIT") count(3, 3);
        else count(2, 64);
        for (const ExprPtr& a : args)
            if (!a->type.numeric() && a->type.kind != Kind::Time && !a->type.bits())
                fail(n, "type mismatch: " + name + " needs numbers, bit strings or TIMEs, not " + a->type.name());
        const Type t = common_of(args, 0, name, n);
        for (ExprPtr& a : args) a = coerce(std::move(a), t, "an argument of " + name);
        b->type = t;
        b->fn = name == "MIN" ? fn_min : name == "MAX" ? fn_max : fn_limit;
    }
    bool k = true;
    for (const ExprPtr& a : args) k = k && a->constant();
    // ABS, MIN, MAX, LIMIT of literals stay literals (ABS(-5) may still be an INT).
    const bool keeps_literal = real_function(name) < 0;
    if (!k) {
        b->args = std::move(args);
        return b;
    }
    b->args = std::move(args);
    ExprPtr c = fold(std::move(b));
    auto& cc = dynamic_cast<Const&>(*c);
    cc.untyped_int = keeps_literal && all_int;
    cc.untyped_real = keeps_literal && lit_int && lit_real;
    if (cc.untyped_int) cc.type = Type::of(Kind::Dint); // as every integer literal
    if (cc.untyped_real) cc.type = Type::of(Kind::Lreal);
    return c;
}

ExprPtr Compiler::shift(const std::string& name, std::vector<ExprPtr> args, const ParseNode& n) {
    // SHL(IN, N), SHR, ROL, ROR: IN a BYTE, WORD or DWORD (its width is the shift's), N an integer.
    if (args.size() != 2) fail(n, name + " takes two arguments (IN, N), not " + std::to_string(args.size()));
    if (untyped(*args[0]))
        fail(*n.children.at(1), name + " of an integer literal: give it a type, e.g. " + name + "(WORD#16#00FF, 4)");
    if (!args[0]->type.bits())
        fail(n, "type mismatch: IN of " + name + " must be BYTE, WORD or DWORD, not " + args[0]->type.name());
    if (untyped(*args[1])) args[1] = coerce(std::move(args[1]), Type::of(Kind::Dint), "N of " + name);
    if (!args[1]->type.integer()) fail(n, "type mismatch: N of " + name + " must be an integer, not " + args[1]->type.name());
    auto b = std::make_unique<Builtin>();
    b->pos = at(n);
    b->fname = name;
    b->type = args[0]->type;
    b->fn = name == "SHL" ? fn_shift<0> : name == "SHR" ? fn_shift<1> : name == "ROL" ? fn_shift<2> : fn_shift<3>;
    const bool k = args[0]->constant() && args[1]->constant();
    b->args = std::move(args);
    return k ? fold(std::move(b)) : std::move(b);
}

ExprPtr Compiler::select(const std::string& name, std::vector<ExprPtr> args, const ParseNode& n) {
    // SEL(G, IN0, IN1): IN0 when G is FALSE. MUX(K, IN0, ..., INn): INk. One common type for the inputs.
    if (args.size() < 3 || (name == "SEL" && args.size() != 3))
        fail(n, name + (name == "SEL" ? " takes three arguments (G, IN0, IN1), not " : " takes K and two or more inputs, not ") +
                    std::to_string(args.size()) + (name == "SEL" ? "" : " arguments"));
    auto s = std::make_unique<Select>();
    s->pos = at(n);
    s->mux = name == "MUX";
    if (s->mux) {
        s->selector = std::move(args[0]);
        if (untyped(*s->selector)) s->selector = coerce(std::move(s->selector), Type::of(Kind::Dint), "K of MUX");
        if (!s->selector->type.integer())
            fail(n, "type mismatch: K of MUX must be an integer, not " + s->selector->type.name());
    } else {
        s->selector = coerce(std::move(args[0]), Type::of(Kind::Bool), "G of SEL");
    }
    Type t = args[1]->type;
    bool strings = true;
    for (std::size_t i = 1; i < args.size(); ++i) {
        strings = strings && args[i]->type.kind == Kind::String;
        if (strings) t.len = std::max(t.len, args[i]->type.len);
    }
    if (!strings) {
        for (std::size_t i = 1; i < args.size(); ++i)
            if (!args[i]->type.elementary())
                fail(n, "type mismatch: the inputs of " + name + " are values, not " + args[i]->type.name());
        t = common_of(args, 1, name, n);
        for (std::size_t i = 1; i < args.size(); ++i) args[i] = coerce(std::move(args[i]), t, "an input of " + name);
    }
    s->type = t;
    for (std::size_t i = 1; i < args.size(); ++i) s->inputs.push_back(std::move(args[i]));
    if (s->selector->constant()) {
        ExecContext none;
        const std::int64_t k = s->selector->eval(none).i;
        if (k < 0 || k >= static_cast<std::int64_t>(s->inputs.size()))
            fail(n, "MUX selector K = " + std::to_string(k) + " outside 0.." + std::to_string(s->inputs.size() - 1));
    }
    return s;
}

ExprPtr Compiler::string_call(const std::string& name, std::vector<ExprPtr> args, const ParseNode& n) {
    auto need = [&](std::size_t strings, std::size_t ints) {
        if (args.size() != strings + ints)
            fail(n, name + " takes " + std::to_string(strings + ints) + " arguments, not " + std::to_string(args.size()));
        for (std::size_t i = 0; i < args.size(); ++i) {
            if (i < strings && args[i]->type.kind != Kind::String)
                fail(n, "type mismatch: argument " + std::to_string(i + 1) + " of " + name + " must be a STRING, not " +
                            args[i]->type.name());
            if (i >= strings) {
                args[i] = coerce(std::move(args[i]), Type::of(Kind::Dint), "argument " + std::to_string(i + 1) + " of " + name);
            }
        }
    };
    if (name == "LEN" || name == "FIND") {
        need(name == "LEN" ? 1 : 2, 0);
        auto e = std::make_unique<StringInt>();
        e->pos = at(n);
        e->type = Type::of(Kind::Int);
        e->fn = name == "LEN" ? fn_len : fn_find;
        e->args = std::move(args);
        return e;
    }
    auto e = std::make_unique<StringFn>();
    e->pos = at(n);
    e->type = Type::of(Kind::String);
    if (name == "CONCAT") {
        if (args.size() < 2) fail(n, "CONCAT takes two or more arguments, not " + std::to_string(args.size()));
        need(args.size(), 0);
        for (const ExprPtr& a : args) e->type.len += a->type.len;
        e->type.len = std::min<std::int64_t>(e->type.len, 1024);
        e->fn = fn_concat;
    } else if (name == "INSERT" || name == "REPLACE") {
        need(2, name == "INSERT" ? 1 : 2);
        e->type.len = std::min<std::int64_t>(args[0]->type.len + args[1]->type.len, 1024);
        e->fn = name == "INSERT" ? fn_insert : fn_replace;
    } else {
        need(1, name == "LEFT" || name == "RIGHT" ? 1 : 2);
        e->type.len = args[0]->type.len;
        e->fn = name == "LEFT" ? fn_left : name == "RIGHT" ? fn_right : name == "MID" ? fn_mid : fn_delete;
    }
    e->args = std::move(args);
    return e;
}

ExprPtr Compiler::call(const ParseNode& n) {
    const ParseNode& id = *n.children.at(0);
    const std::string name = upper(name_of(id));
    const ParseNode& argn = *n.children.back();
    if (n.children.at(1)->is_type<g::index>())
        fail(*n.children[1], "'" + name_of(id) + "[...](...)' calls a function block instance: a statement, not a value");
    std::vector<ExprPtr> positional;
    std::vector<const ParseNode*> named;
    Decl* d = find_decl(name);
    const bool user_fn = d && d->pou->pou == PouType::Pou::function;
    std::vector<const ParseNode*> positional_nodes;
    for (const auto& a : argn.children) {
        if (a->is_type<g::arg_input>() || a->is_type<g::arg_output>()) named.push_back(a.get());
        else if (user_fn) positional_nodes.push_back(a.get()); // compiled below: a VAR_IN_OUT takes a variable
        else positional.push_back(value_expr(*a));
    }
    static const char* const refused[] = {"ADR", "REF", "SIZEOF", "BITADR", "__NEW", "__DELETE"};
    for (const char* r : refused)
        if (name == r) fail(id, name + " is not supported (docs/st.md)");
    if ((name.size() > 10 && name.compare(name.size() - 10, 10, "_TO_STRING") == 0) || name.rfind("STRING_TO_", 0) == 0)
        fail(id, name + ": a conversion to or from STRING is not supported (docs/st.md)");
    if (!user_fn && !named.empty()) fail(*named[0], name_of(id) + " takes its arguments by position");
    if (name == "TIME") {
        if (!positional.empty()) fail(n, "TIME() takes no arguments");
        auto e = std::make_unique<Now>();
        e->pos = at(n);
        e->type = Type::of(Kind::Time);
        return e;
    }
    if (const auto p = name.find("_TO_"); p != std::string::npos) {
        const auto& el = elementary_types();
        const auto from = el.find(name.substr(0, p)), to = el.find(name.substr(p + 4));
        if (from != el.end() && to != el.end() && from->second != Kind::AxisRef && to->second != Kind::AxisRef)
            return conversion(from->second, to->second, std::move(positional), n, false);
    }
    if (name == "TRUNC") {
        if (positional.size() == 1 && positional[0]->type.kind == Kind::Real)
            return conversion(Kind::Real, Kind::Dint, std::move(positional), n, true);
        return conversion(Kind::Lreal, Kind::Dint, std::move(positional), n, true);
    }
    static const char* const builtins[] = {"ABS", "MIN", "MAX", "LIMIT"};
    for (const char* b : builtins)
        if (name == b) return builtin(name, std::move(positional), n);
    if (real_function(name) >= 0) return builtin(name, std::move(positional), n);
    if (name == "SHL" || name == "SHR" || name == "ROL" || name == "ROR") return shift(name, std::move(positional), n);
    if (name == "SEL" || name == "MUX") return select(name, std::move(positional), n);
    static const char* const strings[] = {"LEN", "FIND", "CONCAT", "LEFT", "RIGHT", "MID", "INSERT", "DELETE", "REPLACE"};
    for (const char* b : strings)
        if (name == b) return string_call(name, std::move(positional), n);
    if (!user_fn) {
        if (cur_ && (cur_->find(name) || u_.globals.find(name)))
            fail(id, "'" + name_of(id) + "' is a variable, not a function (a function block instance is called as a "
                     "statement: " + name_of(id) + "(...);)");
        fail(id, "unknown function '" + name_of(id) + "'");
    }
    if (d->state == Decl::State::compiling)
        fail(id, "recursive call of '" + d->pou->name + "' (IEC 61131-3 does not allow recursion)");
    compile_body(*d);
    const PouType& fn = *d->pou;
    auto call = std::make_unique<FunctionCall>();
    call->pos = at(n);
    call->fn = &fn;
    call->type = fn.result;
    call->result_slot = fn.vars.at(fn.index.at(upper(fn.name))).slot;
    // Positional arguments go to VAR_INPUT and VAR_IN_OUT in their declaration order.
    std::vector<const VarInfo*> inputs;
    for (const VarInfo& v : fn.vars)
        if (v.kind == VarKind::input || v.kind == VarKind::in_out) inputs.push_back(&v);
    if (positional_nodes.size() > inputs.size())
        fail(n, fn.name + " has " + std::to_string(inputs.size()) + " inputs, the call gives " +
                    std::to_string(positional_nodes.size()));
    std::vector<const VarInfo*> given;
    auto bind = [&](const VarInfo& v, const ParseNode& value) {
        given.push_back(&v);
        if (v.kind == VarKind::in_out)
            call->in_outs.emplace_back(v.slot, in_out_argument(v, value, fn.name));
        else
            call->inputs.emplace_back(&v, coerce(value_expr(value), v.type, "input " + v.name + " of " + fn.name));
    };
    for (std::size_t i = 0; i < positional_nodes.size(); ++i) bind(*inputs[i], *positional_nodes[i]);
    for (const ParseNode* a : named) {
        const ParseNode& in = *a->children.at(0);
        if (a->is_type<g::arg_output>()) fail(in, "'=>' in a FUNCTION call: functions have no outputs here");
        const VarInfo* v = fn.find(upper(name_of(in)));
        if (!v || (v->kind != VarKind::input && v->kind != VarKind::in_out))
            fail(in, "'" + name_of(in) + "' is not an input of " + fn.name);
        if (std::find(given.begin(), given.end(), v) != given.end()) fail(in, "'" + name_of(in) + "' is given twice");
        bind(*v, *a->children.at(1));
    }
    for (const VarInfo* v : inputs)
        if (v->kind == VarKind::in_out && std::find(given.begin(), given.end(), v) == given.end())
            fail(n, "VAR_IN_OUT '" + v->name + "' of " + fn.name + " is not given (every call names its variable)");
    return call;
}

} // namespace rcsim::st::detail
