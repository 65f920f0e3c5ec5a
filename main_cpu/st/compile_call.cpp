// rcsim — the Structured Text compiler: calls of functions (user FUNCTIONs, the standard
// functions of docs/st.md, the X_TO_Y conversions) in expressions. See compiler.h.
#include "main_cpu/st/compiler_impl.h"
#include "main_cpu/st/grammar.h"

#include <cmath>

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

template <double (*F)(double)> Value real_fn(const Type&, const std::vector<Value>& a, const SourcePos&) {
    return Value{0, F(a[0].r)};
}

Value fn_sqrt(const Type&, const std::vector<Value>& a, const SourcePos& at) {
    if (a[0].r < 0) throw RuntimeError(at.str() + ": SQRT of the negative number " + std::to_string(a[0].r));
    return Value{0, std::sqrt(a[0].r)};
}

double sin_(double x) { return std::sin(x); }
double cos_(double x) { return std::cos(x); }
double atan_(double x) { return std::atan(x); }

} // namespace

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
    } else if (name == "SQRT" || name == "SIN" || name == "COS" || name == "ATAN") {
        count(1, 1);
        b->type = args[0]->type.kind == Kind::Real ? Type::of(Kind::Real) : Type::of(Kind::Lreal);
        args[0] = coerce(std::move(args[0]), b->type, "the argument of " + name);
        b->fn = name == "SQRT" ? fn_sqrt : name == "SIN" ? real_fn<sin_> : name == "COS" ? real_fn<cos_> : real_fn<atan_>;
    } else {
        // MIN, MAX (two or more), LIMIT(MN, IN, MX): one common type for all arguments.
        if (name == "LIMIT") count(3, 3);
        else count(2, 64);
        Type t = args[0]->type;
        for (const ExprPtr& a : args)
            if (!a->type.numeric() && a->type.kind != Kind::Time)
                fail(n, "type mismatch: " + name + " needs numbers or TIMEs, not " + a->type.name());
        for (std::size_t i = 1; i < args.size(); ++i) {
            struct Probe : Expr {
                Value eval(ExecContext&) const override { return {}; }
            } probe;
            probe.type = t;
            t = common_type(probe, *args[i], name, n);
        }
        for (ExprPtr& a : args) a = coerce(std::move(a), t, "an argument of " + name);
        b->type = t;
        b->fn = name == "MIN" ? fn_min : name == "MAX" ? fn_max : fn_limit;
    }
    bool k = true;
    for (const ExprPtr& a : args) k = k && a->constant();
    // ABS, MIN, MAX, LIMIT of literals stay literals (ABS(-5) may still be an INT).
    const bool keeps_literal = name != "SQRT" && name != "SIN" && name != "COS" && name != "ATAN";
    if (!k) {
        b->args = std::move(args);
        return b;
    }
    b->args = std::move(args);
    ExprPtr c = fold(std::move(b));
    auto& cc = dynamic_cast<Const&>(*c);
    cc.untyped_int = keeps_literal && all_int;
    cc.untyped_real = keeps_literal && lit_int && lit_real;
    return c;
}

ExprPtr Compiler::call(const ParseNode& n) {
    const ParseNode& id = *n.children.at(0);
    const std::string name = upper(name_of(id));
    const ParseNode& argn = *n.children.at(1);
    std::vector<ExprPtr> positional;
    std::vector<const ParseNode*> named;
    for (const auto& a : argn.children) {
        if (a->is_type<g::arg_input>() || a->is_type<g::arg_output>()) named.push_back(a.get());
        else positional.push_back(expr(*a));
    }
    Decl* d = find_decl(name);
    const bool user_fn = d && d->pou->pou == PouType::Pou::function;
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
    static const char* const builtins[] = {"ABS", "SQRT", "SIN", "COS", "ATAN", "MIN", "MAX", "LIMIT"};
    for (const char* b : builtins)
        if (name == b) return builtin(name, std::move(positional), n);
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
    std::vector<const VarInfo*> inputs;
    for (const VarInfo& v : fn.vars)
        if (v.kind == VarKind::input) inputs.push_back(&v);
    if (positional.size() > inputs.size())
        fail(n, fn.name + " has " + std::to_string(inputs.size()) + " inputs, the call gives " +
                    std::to_string(positional.size()));
    for (std::size_t i = 0; i < positional.size(); ++i)
        call->inputs.emplace_back(inputs[i]->slot, coerce(std::move(positional[i]), inputs[i]->type,
                                                         "input " + inputs[i]->name + " of " + fn.name));
    for (const ParseNode* a : named) {
        const ParseNode& in = *a->children.at(0);
        if (a->is_type<g::arg_output>()) fail(in, "'=>' in a FUNCTION call: functions have no outputs here");
        const VarInfo* v = fn.find(upper(name_of(in)));
        if (!v || v->kind != VarKind::input) fail(in, "'" + name_of(in) + "' is not an input of " + fn.name);
        call->inputs.emplace_back(v->slot, coerce(expr(*a->children.at(1)), v->type, "input " + v->name + " of " + fn.name));
    }
    return call;
}

} // namespace rcsim::st::detail
