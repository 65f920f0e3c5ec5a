// rcsim — the Structured Text compiler: expressions, literals and the type rules (docs/st.md
// "Expressions"). See compiler.h.
#include "main_cpu/st/compiler_impl.h"
#include "main_cpu/st/grammar.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

namespace rcsim::st::detail {

namespace g = grammar;

bool untyped(const Expr& e) {
    const auto* c = dynamic_cast<const Const*>(&e);
    return c && (c->untyped_int || c->untyped_real);
}

namespace {

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

ExprPtr Compiler::string_literal(const ParseNode& n) {
    // 'text' with IEC 61131-3's escapes (Table 6): $$ $' $L $N $P $R $T and $hh.
    const std::string raw = trim(n.string());
    std::string out;
    for (std::size_t k = 1; k + 1 < raw.size(); ++k) {
        if (raw[k] != '$') {
            out += raw[k];
            continue;
        }
        const char e = static_cast<char>(std::toupper(static_cast<unsigned char>(raw[++k])));
        if (std::isxdigit(static_cast<unsigned char>(e)) && std::isxdigit(static_cast<unsigned char>(raw[k + 1])) &&
            !(e == 'L' || e == 'N' || e == 'P' || e == 'R' || e == 'T')) {
            out += static_cast<char>(std::stoi(raw.substr(k, 2), nullptr, 16));
            ++k;
        } else {
            out += e == 'L' || e == 'N' ? '\n' : e == 'P' ? '\f' : e == 'R' ? '\r' : e == 'T' ? '\t' : raw[k];
        }
    }
    if (out.size() > 1024) fail(n, "a string literal of more than 1024 characters");
    auto c = std::make_unique<Const>();
    c->pos = at(n);
    c->s = out;
    c->type = Type::of(Kind::String);
    c->type.len = std::max<std::int64_t>(1, static_cast<std::int64_t>(out.size()));
    return c;
}

ExprPtr Compiler::typed_literal(const ParseNode& n) {
    // INT#5, WORD#16#FF, REAL#1.5, BOOL#TRUE, BOOL#1, INT#-5, Color#Red (§6.3.2, §6.4.4.2).
    const ParseNode& prefix = *n.children.at(0);
    const ParseNode& value = *n.children.back();
    const bool neg = n.children.size() > 2;
    const std::string text = trim(n.string());
    const Type t = resolve_type(prefix);
    if (value.is_type<g::enum_value>()) {
        if (t.kind != Kind::Enum) fail(n, "'" + text + "': " + t.name() + " has no named values");
        for (const auto& [name, v] : t.en->values)
            if (upper(name) == upper(name_of(value))) {
                auto c = std::make_unique<Const>();
                c->pos = at(n);
                c->type = t;
                c->v.i = v;
                return c;
            }
        fail(value, "'" + name_of(value) + "' is not a value of " + t.name());
    }
    if (t.kind == Kind::Enum || !t.elementary() || t.kind == Kind::AxisRef || t.kind == Kind::Time)
        fail(n, "'" + text + "': a typed literal of " + t.name() + " is not supported");
    ExprPtr c = literal(value);
    auto& k = dynamic_cast<Const&>(*c);
    k.pos = at(n);
    if (neg) {
        if (!k.untyped_int && !k.untyped_real) fail(n, "'" + text + "': only a number takes a sign");
        k.v.i = -k.v.i;
        k.v.r = -k.v.r;
    }
    if (t.kind == Kind::Bool && k.untyped_int && (k.v.i == 0 || k.v.i == 1)) {
        k.untyped_int = false;
        k.type = t;
        return c;
    }
    return coerce(std::move(c), t, "the typed literal '" + text + "'");
}

ExprPtr Compiler::named_constant(const ParseNode& id) {
    const std::string key = upper(name_of(id));
    const Found f = try_lookup(key);
    if (f.var) {
        if (!f.var->constant) return nullptr;
        auto c = std::make_unique<Const>();
        c->pos = at(id);
        c->type = f.var->type;
        if (c->type.kind == Kind::String) c->s = unpack(f.var->init.data());
        else if (c->type.elementary()) c->v = f.var->init.at(0);
        else return nullptr; // a CONSTANT STRUCT or ARRAY is read through its slots
        return c;
    }
    std::unique_ptr<Const> found;
    for (const auto& e : u_.enums)
        for (const auto& [name, v] : e->values)
            if (upper(name) == key) {
                if (found)
                    fail(id, "'" + name_of(id) + "' is a value of " + found->type.name() + " and of " + e->name +
                                 "; write " + e->name + "#" + name);
                found = std::make_unique<Const>();
                found->pos = at(id);
                found->type = Type::of(Kind::Enum);
                found->type.en = e.get();
                found->v.i = v;
            }
    return found;
}

ExprPtr Compiler::value_expr(const ParseNode& n) {
    if (n.is_type<g::variable>() && !(n.children.size() == 1 && named_constant(*n.children[0])))
        return variable(n, false, true);
    return expr(n);
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
    // Any STRING fits any STRING variable: a longer one is cut on the store (§6.4.2).
    if (e->type.kind == Kind::String && to.kind == Kind::String) return e;
    if (auto* c = dynamic_cast<Const*>(e.get()); c && (c->untyped_int || c->untyped_real)) {
        if (c->untyped_int && (to.integer() || to.bits())) {
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
    const bool bits = a->type.bits() || b->type.bits();
    if ((op == Op::and_ || op == Op::or_ || op == Op::xor_) && (bits || (untyped(*a) && untyped(*b)))) {
        // On the bit strings, bit by bit (Table 28); two integer literals stay a literal.
        for (const Expr* x : {a.get(), b.get()})
            if (!x->type.bits() && !(untyped(*x) && dynamic_cast<const Const&>(*x).untyped_int))
                fail(at_node, "type mismatch: the operands of " + sym + " are " + describe(*a) + " and " + describe(*b) +
                                  " (both BOOL, or both BYTE, WORD, DWORD)");
        const Type t = untyped(*a) && untyped(*b) ? Type::of(Kind::Dint) : common_type(*a, *b, sym, at_node);
        untyped_int = untyped(*a) && untyped(*b);
        if (!untyped_int) {
            a = coerce(std::move(a), t, "the left operand of " + sym);
            b = coerce(std::move(b), t, "the right operand of " + sym);
        }
        node->operand = node->type = t;
    } else if (op == Op::and_ || op == Op::or_ || op == Op::xor_) {
        a = coerce(std::move(a), Type::of(Kind::Bool), "the left operand of " + sym);
        b = coerce(std::move(b), Type::of(Kind::Bool), "the right operand of " + sym);
        node->operand = node->type = Type::of(Kind::Bool);
    } else if (ka == Kind::String || kb == Kind::String) {
        if (ka != kb || !comparison(op))
            fail(at_node, "type mismatch: '" + sym + "' is not defined for " + describe(*a) + " and " + describe(*b) +
                              (ka == kb ? " (CONCAT joins strings)" : ""));
        auto sc = std::make_unique<StringCompare>();
        sc->op = op;
        sc->pos = node->pos;
        sc->type = Type::of(Kind::Bool);
        sc->a = std::move(a);
        sc->b = std::move(b);
        return both_const ? fold(std::move(sc)) : std::move(sc);
    } else if (comparison(op) && (bits || ka == Kind::Enum || kb == Kind::Enum)) {
        // Bit strings compare as unsigned numbers; values of one enumeration only for equality.
        if ((ka == Kind::Enum || kb == Kind::Enum) && (a->type != b->type || (op != Op::eq && op != Op::ne)))
            fail(at_node, "type mismatch: '" + sym + "' is not defined for " + describe(*a) + " and " + describe(*b));
        const Type t = common_type(*a, *b, sym, at_node);
        if (!t.bits() && t.kind != Kind::Enum)
            fail(at_node, "type mismatch: '" + sym + "' is not defined for " + describe(*a) + " and " + describe(*b));
        a = coerce(std::move(a), t, "the left operand of '" + sym + "'");
        b = coerce(std::move(b), t, "the right operand of '" + sym + "'");
        node->operand = t;
        node->type = Type::of(Kind::Bool);
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
        if (lit_int) fail(op, "NOT of an integer literal: give it a type, e.g. NOT WORD#16#FF");
        if (!a->type.bits()) a = coerce(std::move(a), Type::of(Kind::Bool), "the operand of NOT");
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

LValuePtr Compiler::place(const Found& f, const ParseNode& id) {
    auto r = std::make_unique<LValue>();
    r->base = f.var->kind == VarKind::in_out ? LValue::Base::in_out
              : f.global                     ? LValue::Base::global
                                             : LValue::Base::self;
    r->slot = f.var->slot;
    r->type = f.var->type;
    r->read_only = f.var->read_only;
    r->name = f.var->name;
    r->pos = at(id);
    return r;
}

LValuePtr Compiler::variable(const ParseNode& n, bool for_write, bool whole) {
    // name, then members (of an FB instance: its inputs and outputs; of a STRUCT: its members) and
    // indices, each step narrowing the place: a fixed offset, an index checked when it runs.
    const ParseNode& id = *n.children.at(0);
    const Found f = lookup(id);
    LValuePtr r = place(f, id);
    bool output = false; // an FB's output: only the block writes it
    for (std::size_t k = 1; k < n.children.size(); ++k) {
        const ParseNode& sub = *n.children[k];
        const Type t = r->type;
        if (sub.is_type<g::member>()) {
            const ParseNode& mid = *sub.children.at(0);
            if (t.kind == Kind::Fb) {
                const VarInfo* m = t.fb->find(upper(name_of(mid)));
                if (!m || (m->kind != VarKind::input && m->kind != VarKind::output))
                    fail(mid, "'" + name_of(mid) + "' is not an input or output of " + t.name());
                if (r->base == LValue::Base::fb_member || r->offset || r->indices.size() > 1)
                    fail(mid, "only one function block instance in a name is in this subset");
                r->inst = InstancePath{};
                r->inst.global = r->base == LValue::Base::global;
                r->inst.slot = r->slot;
                if (!r->indices.empty()) { // t[i].Q: the index picks the instance
                    r->inst.index = std::move(r->indices.front().index);
                    r->inst.lo = r->indices.front().lo;
                    r->inst.hi = r->indices.front().hi;
                    r->inst.pos = r->pos;
                    r->inst.name = f.var->name;
                    r->indices.clear();
                }
                r->base = LValue::Base::fb_member;
                r->slot = m->slot;
                r->type = m->type;
                output = m->kind == VarKind::output;
            } else if (t.kind == Kind::Struct) {
                const StructType::Member* m = t.st->find(upper(name_of(mid)));
                if (!m) fail(mid, "'" + name_of(mid) + "' is not a member of " + t.name());
                r->offset += m->offset;
                r->type = m->type;
            } else {
                fail(mid, "'" + r->name + "' is " + t.name() + "; it has no members");
            }
            r->name += "." + name_of(mid);
            continue;
        }
        if (t.kind != Kind::Array) fail(sub, "'" + r->name + "' is " + t.name() + ", not an ARRAY");
        ExprPtr idx = expr(*sub.children.at(0));
        if (untyped(*idx)) idx = coerce(std::move(idx), Type::of(Kind::Dint), "an array index");
        if (!idx->type.integer()) fail(*sub.children[0], "type mismatch: an array index must be an integer, not " + idx->type.name());
        if (idx->constant()) {
            ExecContext none;
            const std::int64_t i = idx->eval(none).i;
            if (i < t.lo || i > t.hi)
                fail(*sub.children[0], "index " + std::to_string(i) + " outside " + r->name + "[" +
                                           std::to_string(t.lo) + ".." + std::to_string(t.hi) + "]");
        }
        r->indices.push_back(LValue::Index{std::move(idx), t.lo, t.hi, t.element().slots()});
        r->type = t.element();
    }
    const Type& t = r->type;
    if (t.kind == Kind::Fb)
        fail(id, "'" + name_of(id) + "' is a " + t.name() + " instance, not a value (use its outputs, e.g. " +
                     name_of(id) + ".Q)");
    if (t.fb_array())
        fail(id, "'" + r->name + "' is an ARRAY of " + t.fb->name + " instances, not a value (use one's outputs, e.g. " +
                     r->name + "[" + std::to_string(t.lo) + "].Q)");
    if (t.kind == Kind::Array && !whole) fail(id, "'" + r->name + "' is an ARRAY; index it: " + r->name + "[i]");
    if (t.kind == Kind::Struct && !whole)
        fail(id, "'" + r->name + "' is a STRUCT " + t.name() + "; use its members, e.g. " + r->name + "." +
                     t.st->members.front().name);
    if (for_write && output)
        fail(id, "'" + r->name + "' is an output of " + f.var->type.name() + " and only the block writes it");
    if (for_write && f.var->constant) fail(id, "'" + f.var->name + "' is a CONSTANT");
    if (for_write && r->read_only) fail(id, "'" + r->name + "' is read-only");
    r->read_only = r->read_only || output;
    return r;
}

ExprPtr Compiler::expr(const ParseNode& n) {
    if (n.is_type<g::int_lit>() || n.is_type<g::real_lit>() || n.is_type<g::time_lit>() || n.is_type<g::bool_lit>())
        return literal(n);
    if (n.is_type<g::typed_lit>()) return typed_literal(n);
    if (n.is_type<g::string_lit>()) return string_literal(n);
    if (n.is_type<g::negation>()) return unary(n);
    if (n.is_type<g::paren>()) return expr(*n.children.at(0));
    if (n.is_type<g::power>() || n.is_type<g::term>() || n.is_type<g::sum>() || n.is_type<g::comparison>() ||
        n.is_type<g::equality>() || n.is_type<g::conjunction>() || n.is_type<g::exclusive>() ||
        n.is_type<g::disjunction>())
        return binary_chain(n);
    if (n.is_type<g::call>()) return call(n);
    if (n.is_type<g::variable>()) {
        if (n.children.size() == 1)
            if (ExprPtr c = named_constant(*n.children[0])) return c;
        return variable(n, false);
    }
    fail(n, "expected an expression");
}

} // namespace rcsim::st::detail
