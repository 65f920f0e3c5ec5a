// rcsim — the Structured Text compiler: expressions, literals and the type rules (docs/st.md
// "Expressions"). See compiler.h.
#include "main_cpu/st/compiler_impl.h"
#include "main_cpu/st/grammar.h"

#include <cmath>
#include <limits>

namespace rcsim::st::detail {

namespace g = grammar;

namespace {

bool untyped(const Expr& e) {
    const auto* c = dynamic_cast<const Const*>(&e);
    return c && (c->untyped_int || c->untyped_real);
}

std::string describe(const Expr& e) {
    if (const auto* c = dynamic_cast<const Const*>(&e)) {
        if (c->untyped_int) return "an integer literal";
        if (c->untyped_real) return "a real literal";
    }
    return e.type.name();
}

const std::map<std::string, Op>& operators() {
    static const std::map<std::string, Op> m{
        {"**", Op::pow}, {"*", Op::mul}, {"/", Op::div},  {"MOD", Op::mod}, {"+", Op::add},  {"-", Op::sub},
        {"<", Op::lt},   {"<=", Op::le}, {">", Op::gt},   {">=", Op::ge},   {"=", Op::eq},   {"<>", Op::ne},
        {"AND", Op::and_}, {"&", Op::and_}, {"XOR", Op::xor_}, {"OR", Op::or_}};
    return m;
}

bool comparison(Op op) { return op >= Op::lt && op <= Op::ne; }

} // namespace

std::int64_t Compiler::integer_literal(const std::string& text, const ParseNode& n) {
    std::string s = strip_underscores(text);
    bool neg = false;
    if (!s.empty() && s[0] == '-') {
        neg = true;
        s.erase(0, 1);
    }
    unsigned base = 10;
    if (const auto hash = s.find('#'); hash != std::string::npos) {
        base = static_cast<unsigned>(std::stoul(s.substr(0, hash)));
        s.erase(0, hash + 1);
    }
    std::uint64_t v = 0;
    for (char ch : s) {
        const unsigned d = std::isdigit(static_cast<unsigned char>(ch)) ? static_cast<unsigned>(ch - '0')
                                                                         : static_cast<unsigned>(std::toupper(ch) - 'A' + 10);
        if (d >= base) fail(n, "'" + text + "' is not a base-" + std::to_string(base) + " number");
        if (v > (static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) - d) / base)
            fail(n, "the integer literal '" + text + "' is too large");
        v = v * base + d;
    }
    return neg ? -static_cast<std::int64_t>(v) : static_cast<std::int64_t>(v);
}

std::int64_t Compiler::time_literal(const std::string& text, const ParseNode& n) {
    // T#1d2h3m4s5ms6us7ns: each unit at most once, largest first (§6.3.3, Table 8).
    static const std::pair<const char*, double> units[] = {{"D", 86400e6}, {"H", 3600e6}, {"M", 60e6}, {"S", 1e6},
                                                           {"MS", 1e3},    {"US", 1},     {"NS", 1e-3}};
    std::string s = upper(strip_underscores(text.substr(text.find('#') + 1)));
    bool neg = false;
    if (!s.empty() && s[0] == '-') {
        neg = true;
        s.erase(0, 1);
    }
    double us = 0;
    int last = -1;
    std::size_t i = 0;
    while (i < s.size()) {
        std::size_t j = i;
        while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.')) ++j;
        const double num = std::stod(s.substr(i, j - i));
        std::size_t k = j;
        while (k < s.size() && std::isalpha(static_cast<unsigned char>(s[k]))) ++k;
        // "1m30s" has "M" then "30S": a letter run may hold only one unit; take the longest match.
        std::string unit = s.substr(j, k - j);
        if (unit.size() > 2 || (unit.size() == 2 && unit != "MS" && unit != "US" && unit != "NS")) unit = unit.substr(0, 1);
        int rank = -1;
        for (int u = 0; u < 7; ++u)
            if (unit == units[u].first) rank = u;
        if (rank <= last) fail(n, "the units of '" + text + "' must go from d down to ns, each at most once");
        last = rank;
        us += num * units[rank].second;
        i = j + unit.size();
    }
    if (us > 9.2e18) fail(n, "'" + text + "' is too long a time");
    return neg ? -std::llround(us) : std::llround(us);
}

ExprPtr Compiler::literal(const ParseNode& n) {
    auto c = std::make_unique<Const>();
    c->pos = at(n);
    const std::string text = trim(n.string());
    if (n.is_type<g::int_lit>()) {
        c->v.i = integer_literal(text, n);
        c->type = Type::of(Kind::Dint);
        c->untyped_int = true;
    } else if (n.is_type<g::real_lit>()) {
        c->v.r = std::stod(strip_underscores(text));
        c->type = Type::of(Kind::Lreal);
        c->untyped_real = true;
    } else if (n.is_type<g::time_lit>()) {
        c->v.i = time_literal(text, n);
        c->type = Type::of(Kind::Time);
    } else {
        c->v.i = upper(text) == "TRUE";
        c->type = Type::of(Kind::Bool);
    }
    return c;
}

ExprPtr Compiler::fold(ExprPtr e) {
    ExecContext none;
    auto c = std::make_unique<Const>();
    c->pos = e->pos;
    c->type = e->type;
    try {
        c->v = e->eval(none);
    } catch (const RuntimeError& x) {
        throw CompileError(x.what());
    }
    return c;
}

ExprPtr Compiler::coerce(ExprPtr e, const Type& to, const std::string& what) {
    if (e->type == to && !untyped(*e)) return e;
    if (auto* c = dynamic_cast<Const*>(e.get()); c && (c->untyped_int || c->untyped_real)) {
        if (c->untyped_int && to.integer()) {
            if (!fits(to.kind, c->v.i))
                throw CompileError(e->pos.str() + ": the literal " + std::to_string(c->v.i) + " does not fit in " +
                                   to.name() + " (" + what + ")");
            c->type = to;
            c->untyped_int = false;
            return e;
        }
        if (to.real()) {
            if (c->untyped_int) c->v.r = static_cast<double>(c->v.i);
            c->v = normalise(to.kind, c->v);
            c->type = to;
            c->untyped_int = c->untyped_real = false;
            return e;
        }
    } else if (e->type.elementary() && widens(e->type.kind, to.kind)) {
        auto cv = std::make_unique<Convert>();
        cv->pos = e->pos;
        cv->type = to;
        const bool k = e->constant();
        cv->a = std::move(e);
        return k ? fold(std::move(cv)) : std::move(cv);
    }
    throw CompileError(e->pos.str() + ": type mismatch: " + what + " must be " + to.name() + ", not " + describe(*e));
}

Type Compiler::common_type(const Expr& a, const Expr& b, const std::string& sym, const ParseNode& at_node) {
    if (untyped(a)) return b.type;
    if (untyped(b)) return a.type;
    if (a.type == b.type) return a.type;
    if (widens(a.type.kind, b.type.kind)) return b.type;
    if (widens(b.type.kind, a.type.kind)) return a.type;
    fail(at_node, "type mismatch: the operands of '" + sym + "' are " + a.type.name() + " and " + b.type.name() +
                      " (convert one, e.g. " + a.type.name() + "_TO_" + b.type.name() + ")");
}

ExprPtr Compiler::binary(Op op, const std::string& sym, ExprPtr a, ExprPtr b, const ParseNode& at_node) {
    auto node = std::make_unique<Binary>();
    node->op = op;
    node->pos = at(at_node);
    const bool both_const = a->constant() && b->constant();
    bool untyped_int = false, untyped_real = false;
    const Kind ka = a->type.kind, kb = b->type.kind;
    if (op == Op::and_ || op == Op::or_ || op == Op::xor_) {
        a = coerce(std::move(a), Type::of(Kind::Bool), "the left operand of " + sym);
        b = coerce(std::move(b), Type::of(Kind::Bool), "the right operand of " + sym);
        node->operand = node->type = Type::of(Kind::Bool);
    } else if (ka == Kind::Time || kb == Kind::Time) {
        // TIME +/- TIME, TIME * or / a number (IEC 61131-3 Table 30), TIME comparisons.
        if (ka == Kind::Time && kb == Kind::Time && (op == Op::add || op == Op::sub || comparison(op))) {
            node->operand = Type::of(Kind::Time);
            node->type = comparison(op) ? Type::of(Kind::Bool) : node->operand;
        } else if (ka == Kind::Time && (op == Op::mul || op == Op::div) && (b->type.numeric())) {
            b = coerce(std::move(b), Type::of(Kind::Lreal), "the factor of a TIME");
            node->operand = Type::of(Kind::Lreal);
            node->type = Type::of(Kind::Time);
        } else {
            fail(at_node, "type mismatch: '" + sym + "' is not defined for " + describe(*a) + " and " + describe(*b));
        }
    } else if ((ka == Kind::Bool || ka == Kind::AxisRef) && kb == ka && (op == Op::eq || op == Op::ne)) {
        node->operand = a->type;
        node->type = Type::of(Kind::Bool);
    } else {
        for (const Expr* x : {a.get(), b.get()})
            if (!x->type.numeric())
                fail(at_node, "type mismatch: '" + sym + "' needs numbers, not " + x->type.name());
        Type t;
        if (untyped(*a) && untyped(*b)) {
            // Two literals: folded here, the result stays untyped (2 + 3 may still become an INT).
            untyped_real = dynamic_cast<Const&>(*a).untyped_real || dynamic_cast<Const&>(*b).untyped_real ||
                           op == Op::pow;
            untyped_int = !untyped_real && !comparison(op);
            untyped_real = untyped_real && !comparison(op);
            t = (dynamic_cast<Const&>(*a).untyped_real || dynamic_cast<Const&>(*b).untyped_real || op == Op::pow)
                    ? Type::of(Kind::Lreal) : Type::of(Kind::Void);
        } else {
            t = common_type(*a, *b, sym, at_node);
            if (op == Op::pow && t.integer()) t = Type::of(Kind::Lreal);
        }
        if (op == Op::mod && !(t.integer() || t.kind == Kind::Void))
            fail(at_node, "type mismatch: MOD needs integer operands, not " + t.name());
        if (t.kind != Kind::Void) {
            a = coerce(std::move(a), t, "the left operand of '" + sym + "'");
            b = coerce(std::move(b), t, "the right operand of '" + sym + "'");
        }
        node->operand = t;
        node->type = comparison(op) ? Type::of(Kind::Bool) : t;
    }
    node->a = std::move(a);
    node->b = std::move(b);
    if (!both_const) return node;
    ExprPtr c = fold(std::move(node));
    auto& k = dynamic_cast<Const&>(*c);
    k.untyped_int = untyped_int;
    k.untyped_real = untyped_real;
    if (untyped_int) k.type = Type::of(Kind::Dint);
    return c;
}

ExprPtr Compiler::binary_chain(const ParseNode& n) {
    // The tree is left-deep: its evaluation recurses once per operator.
    if (n.children.size() > 2 * 1000)
        fail(*n.children[2 * 1000 - 1], "more than 1000 operators of one precedence in a row");
    ExprPtr acc = expr(*n.children.at(0));
    for (std::size_t i = 1; i + 1 < n.children.size(); i += 2) {
        const ParseNode& op = *n.children[i];
        const std::string sym = upper(trim(op.string()));
        acc = binary(operators().at(sym), sym, std::move(acc), expr(*n.children[i + 1]), op);
    }
    return acc;
}

ExprPtr Compiler::unary(const ParseNode& n) {
    const ParseNode& op = *n.children.at(0);
    ExprPtr a = expr(*n.children.at(1));
    auto u = std::make_unique<Unary>();
    u->pos = at(op);
    const bool lit = untyped(*a);
    const bool lit_int = lit && dynamic_cast<Const&>(*a).untyped_int;
    if (op.is_type<g::op_not>()) {
        u->op = Op::not_;
        a = coerce(std::move(a), Type::of(Kind::Bool), "the operand of NOT");
    } else {
        u->op = Op::neg;
        if (!a->type.numeric() && a->type.kind != Kind::Time)
            fail(op, "type mismatch: '-' needs a number or a TIME, not " + a->type.name());
        if (lit_int) a->type = Type::of(Kind::Void); // negated in 64 bits, typed where it is used
    }
    u->type = a->type;
    const bool k = a->constant();
    u->a = std::move(a);
    if (!k) return u;
    ExprPtr c = fold(std::move(u));
    auto& cc = dynamic_cast<Const&>(*c);
    if (lit_int) {
        cc.untyped_int = true;
        cc.type = Type::of(Kind::Dint);
    } else if (lit) {
        cc.untyped_real = true;
    }
    return c;
}

LValuePtr Compiler::variable(const ParseNode& n, bool for_write) {
    const ParseNode& id = *n.children.at(0);
    const Found f = lookup(id);
    const Type& t = f.var->type;
    if (n.children.size() > 2) fail(*n.children[2], "only one member or index after a name is in this subset");
    if (n.children.size() == 1) {
        if (t.kind == Kind::Fb)
            fail(id, "'" + name_of(id) + "' is a " + t.name() + " instance, not a value (use its outputs, e.g. " +
                         name_of(id) + ".Q)");
        if (t.kind == Kind::Array) fail(id, "'" + name_of(id) + "' is an ARRAY; index it: " + name_of(id) + "[i]");
        auto r = std::make_unique<VarRef>();
        r->global = f.global;
        r->slot = f.var->slot;
        r->type = t;
        r->read_only = f.var->read_only;
        r->name = f.var->name;
        r->pos = at(id);
        if (for_write && r->read_only) fail(id, "'" + r->name + "' is read-only");
        return r;
    }
    const ParseNode& sub = *n.children[1];
    if (sub.is_type<g::member>()) {
        const ParseNode& mid = *sub.children.at(0);
        if (t.kind != Kind::Fb) fail(mid, "'" + name_of(id) + "' is " + t.name() + "; it has no members");
        const VarInfo* m = t.fb->find(upper(name_of(mid)));
        if (!m || (m->kind != VarKind::input && m->kind != VarKind::output))
            fail(mid, "'" + name_of(mid) + "' is not an input or output of " + t.name());
        if (!m->type.elementary()) fail(mid, "'" + name_of(mid) + "' is not of an elementary type");
        auto r = std::make_unique<MemberRef>();
        r->inst = InstancePath{f.global, f.var->slot};
        r->slot = m->slot;
        r->type = m->type;
        r->name = f.var->name + "." + m->name;
        r->pos = at(id);
        r->read_only = m->kind == VarKind::output;
        if (for_write && r->read_only)
            fail(id, "'" + r->name + "' is an output of " + t.name() + " and only the block writes it");
        return r;
    }
    if (t.kind != Kind::Array) fail(sub, "'" + name_of(id) + "' is " + t.name() + ", not an ARRAY");
    ExprPtr idx = expr(*sub.children.at(0));
    if (untyped(*idx)) idx = coerce(std::move(idx), Type::of(Kind::Dint), "an array index");
    if (!idx->type.integer()) fail(*sub.children[0], "type mismatch: an array index must be an integer, not " + idx->type.name());
    if (idx->constant()) {
        ExecContext none;
        const std::int64_t i = idx->eval(none).i;
        if (i < t.lo || i > t.hi)
            fail(*sub.children[0], "index " + std::to_string(i) + " outside " + name_of(id) + "[" +
                                       std::to_string(t.lo) + ".." + std::to_string(t.hi) + "]");
    }
    auto r = std::make_unique<IndexRef>();
    r->global = f.global;
    r->base = f.var->slot;
    r->lo = t.lo;
    r->hi = t.hi;
    r->index = std::move(idx);
    r->type = Type::of(t.elem);
    r->name = f.var->name;
    r->pos = at(id);
    return r;
}

ExprPtr Compiler::expr(const ParseNode& n) {
    if (n.is_type<g::int_lit>() || n.is_type<g::real_lit>() || n.is_type<g::time_lit>() || n.is_type<g::bool_lit>())
        return literal(n);
    if (n.is_type<g::negation>()) return unary(n);
    if (n.is_type<g::paren>()) return expr(*n.children.at(0));
    if (n.is_type<g::power>() || n.is_type<g::term>() || n.is_type<g::sum>() || n.is_type<g::comparison>() ||
        n.is_type<g::equality>() || n.is_type<g::conjunction>() || n.is_type<g::exclusive>() ||
        n.is_type<g::disjunction>())
        return binary_chain(n);
    if (n.is_type<g::call>()) return call(n);
    if (n.is_type<g::variable>()) return variable(n, false);
    fail(n, "expected an expression");
}

} // namespace rcsim::st::detail
