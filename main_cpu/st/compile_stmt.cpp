// rcsim — the Structured Text compiler: statements (IEC 61131-3 §7.3.3). See compiler.h.
#include "main_cpu/st/compiler_impl.h"
#include "main_cpu/st/grammar.h"

#include <algorithm>

namespace rcsim::st::detail {

namespace g = grammar;

namespace {

/// Whether a value of type `from` may be stored in `to` (same type or a widening).
bool assignable(const Type& from, const Type& to) {
    return from == to || (from.elementary() && widens(from.kind, to.kind)) ||
           (from.kind == Kind::String && to.kind == Kind::String);
}

} // namespace

Block Compiler::statements(const ParseNode& n) {
    Block b;
    for (const auto& s : n.children) b.push_back(statement(*s));
    return b;
}

ExprPtr Compiler::condition(const ParseNode& n, const char* what) {
    return coerce(expr(n), Type::of(Kind::Bool), std::string("the condition of ") + what);
}

StmtPtr Compiler::statement(const ParseNode& n) {
    StmtPtr s;
    if (n.is_type<g::assignment>()) s = assignment(n);
    else if (n.is_type<g::call_stmt>()) s = fb_call(*n.children.at(0));
    else if (n.is_type<g::if_stmt>()) s = if_stmt(n);
    else if (n.is_type<g::case_stmt>()) s = case_stmt(n);
    else if (n.is_type<g::for_stmt>()) s = for_stmt(n);
    else if (n.is_type<g::while_stmt>()) {
        auto w = std::make_unique<While>();
        w->cond = condition(*n.children.at(0), "WHILE");
        ++loops_;
        w->body = statements(*n.children.at(1));
        --loops_;
        s = std::move(w);
    } else if (n.is_type<g::repeat_stmt>()) {
        auto r = std::make_unique<Repeat>();
        ++loops_;
        r->body = statements(*n.children.at(0));
        --loops_;
        r->until = condition(*n.children.at(1), "UNTIL");
        s = std::move(r);
    } else if (n.is_type<g::exit_stmt>()) {
        if (loops_ == 0) fail(n, "EXIT outside FOR, WHILE or REPEAT");
        s = std::make_unique<Exit>();
    } else if (n.is_type<g::continue_stmt>()) {
        if (loops_ == 0) fail(n, "CONTINUE outside FOR, WHILE or REPEAT");
        s = std::make_unique<Continue>();
    } else if (n.is_type<g::return_stmt>()) {
        s = std::make_unique<Return>();
    } else {
        fail(n, "expected a statement");
    }
    s->pos = at(n);
    return s;
}

StmtPtr Compiler::assignment(const ParseNode& n) {
    auto a = std::make_unique<Assign>();
    a->target = variable(*n.children.at(0), true, true);
    a->value = coerce(value_expr(*n.children.at(1)), a->target->type,
                      "the value assigned to '" + a->target->name + "'");
    return a;
}

LValuePtr Compiler::in_out_argument(const VarInfo& v, const ParseNode& value, const std::string& pou) {
    // IEC 61131-3 §6.5.2.2: a VAR_IN_OUT is given a variable of its own type, which the callee
    // reads and writes in place (for a STRING, of the same length: the callee writes that many).
    if (!value.is_type<g::variable>())
        fail(value, "VAR_IN_OUT '" + v.name + "' of " + pou + " needs a variable, not an expression");
    LValuePtr var = variable(value, true, true);
    if (var->type != v.type)
        fail(value, "type mismatch: VAR_IN_OUT '" + v.name + "' of " + pou + " is " + v.type.name() + ", '" + var->name +
                        "' is " + var->type.name());
    return var;
}

StmtPtr Compiler::fb_call(const ParseNode& n) {
    const ParseNode& id = *n.children.at(0);
    const std::string key = upper(name_of(id));
    if (Decl* d = find_decl(key); d && d->pou->pou == PouType::Pou::function)
        fail(id, "'" + d->pou->name + "' is a FUNCTION: use its result, e.g. x := " + d->pou->name + "(...);");
    const Found f = lookup(id);
    const Type& ft = f.var->type;
    const bool indexed = n.children.at(1)->is_type<g::index>();
    if (indexed && !ft.fb_array())
        fail(id, "'" + name_of(id) + "' is " + ft.name() + ", not an ARRAY of function block instances");
    if (!indexed && ft.fb_array())
        fail(id, "'" + name_of(id) + "' is " + ft.name() + "; call one element: " + name_of(id) + "[" +
                     std::to_string(ft.lo) + "](...)");
    if (ft.kind != Kind::Fb && !indexed)
        fail(id, "'" + name_of(id) + "' is " + ft.name() + ", not a function block instance");
    const PouType& fb = *ft.fb;
    auto call = std::make_unique<FbCall>();
    call->inst.global = f.global;
    call->inst.slot = f.var->slot;
    if (indexed) {
        const ParseNode& ix = *n.children[1]->children.at(0);
        ExprPtr i = expr(ix);
        if (untyped(*i)) i = coerce(std::move(i), Type::of(Kind::Dint), "an array index");
        if (!i->type.integer()) fail(ix, "type mismatch: an array index must be an integer, not " + i->type.name());
        ExecContext none;
        if (i->constant() && (i->eval(none).i < ft.lo || i->eval(none).i > ft.hi))
            fail(ix, "index " + std::to_string(i->eval(none).i) + " outside " + f.var->name + "[" +
                         std::to_string(ft.lo) + ".." + std::to_string(ft.hi) + "]");
        call->inst.index = std::move(i);
        call->inst.lo = ft.lo;
        call->inst.hi = ft.hi;
        call->inst.pos = at(id);
        call->inst.name = f.var->name;
    }
    std::vector<std::string> seen;
    std::vector<const VarInfo*> in_outs;
    for (const VarInfo& v : fb.vars)
        if (v.kind == VarKind::in_out) in_outs.push_back(&v);
    for (const auto& a : n.children.back()->children) {
        if (!a->is_type<g::arg_input>() && !a->is_type<g::arg_output>())
            fail(*a, "the arguments of a function block call are named: " + name_of(id) + "(IN := value, Q => variable)");
        const ParseNode& pn = *a->children.at(0);
        const std::string pk = upper(name_of(pn));
        if (std::find(seen.begin(), seen.end(), pk) != seen.end()) fail(pn, "'" + name_of(pn) + "' is given twice");
        seen.push_back(pk);
        const VarInfo* v = fb.find(pk);
        if (a->is_type<g::arg_input>() && v && v->kind == VarKind::in_out) {
            call->in_outs.emplace_back(v->slot, in_out_argument(*v, *a->children.at(1), fb.name));
        } else if (a->is_type<g::arg_input>()) {
            if (!v || v->kind != VarKind::input) fail(pn, "'" + name_of(pn) + "' is not an input of " + fb.name);
            call->inputs.emplace_back(v, coerce(value_expr(*a->children.at(1)), v->type,
                                                "input " + v->name + " of " + fb.name));
        } else {
            if (!v || v->kind != VarKind::output) fail(pn, "'" + name_of(pn) + "' is not an output of " + fb.name);
            LValuePtr dest = variable(*a->children.at(1), true, true);
            if (!assignable(v->type, dest->type))
                fail(*a->children[1], "type mismatch: output " + v->name + " of " + fb.name + " is " + v->type.name() +
                                          ", '" + dest->name + "' is " + dest->type.name());
            call->outputs.emplace_back(v, std::move(dest));
        }
    }
    for (const VarInfo* v : in_outs)
        if (std::find(seen.begin(), seen.end(), upper(v->name)) == seen.end())
            fail(id, "VAR_IN_OUT '" + v->name + "' of " + fb.name + " is not given (every call names its variable)");
    return call;
}

StmtPtr Compiler::if_stmt(const ParseNode& n) {
    auto s = std::make_unique<If>();
    s->branches.emplace_back(condition(*n.children.at(0), "IF"), statements(*n.children.at(1)));
    for (std::size_t i = 2; i < n.children.size(); ++i) {
        const ParseNode& part = *n.children[i];
        if (part.is_type<g::elsif_part>())
            s->branches.emplace_back(condition(*part.children.at(0), "ELSIF"), statements(*part.children.at(1)));
        else
            s->otherwise = statements(*part.children.at(0));
    }
    return s;
}

StmtPtr Compiler::case_stmt(const ParseNode& n) {
    auto s = std::make_unique<Case>();
    s->selector = expr(*n.children.at(0));
    if (s->selector->constant() && dynamic_cast<Const&>(*s->selector).untyped_int)
        s->selector = coerce(std::move(s->selector), Type::of(Kind::Dint), "the CASE selector");
    const Type sel = s->selector->type;
    if (!sel.integer() && sel.kind != Kind::Enum)
        fail(*n.children[0], "type mismatch: the CASE selector must be an integer or an enumeration, not " + sel.name());
    for (std::size_t i = 1; i < n.children.size(); ++i) {
        const ParseNode& part = *n.children[i];
        if (part.is_type<g::else_part>()) {
            s->otherwise = statements(*part.children.at(0));
            continue;
        }
        Case::Element e;
        for (const auto& range : part.children.at(0)->children) {
            const std::int64_t lo = case_label(*range->children.at(0), sel);
            const std::int64_t hi = range->children.size() > 1 ? case_label(*range->children[1], sel) : lo;
            std::string label = std::to_string(lo) + (hi != lo ? ".." + std::to_string(hi) : "");
            if (sel.kind == Kind::Enum) label = sel.en->value_name(lo) + (hi != lo ? ".." + sel.en->value_name(hi) : "");
            if (!fits(sel.kind, lo) || !fits(sel.kind, hi))
                fail(*range, "the CASE label " + label + " is outside " + sel.name());
            if (hi < lo) fail(*range, "the CASE range " + label + " is empty");
            for (const Case::Element& other : s->elements)
                for (const auto& [a, b] : other.ranges)
                    if (lo <= b && a <= hi) fail(*range, "the CASE label " + label + " is already used");
            for (const auto& [a, b] : e.ranges)
                if (lo <= b && a <= hi) fail(*range, "the CASE label " + label + " is already used");
            e.ranges.emplace_back(lo, hi);
        }
        e.body = statements(*part.children.at(1));
        s->elements.push_back(std::move(e));
    }
    return s;
}

std::int64_t Compiler::case_label(const ParseNode& n, const Type& sel) {
    // An integer, a typed literal (INT#5, Color#Red), an enumeration value or a CONSTANT.
    if (n.is_type<g::signed_int>()) {
        if (sel.kind == Kind::Enum) fail(n, "the CASE selector is " + sel.name() + ": its labels are its values");
        return integer_literal(trim(n.string()), n);
    }
    ExprPtr e = n.is_type<g::typed_lit>() ? typed_literal(n) : named_constant(n);
    if (!e) fail(n, "the CASE label '" + name_of(n) + "' is neither a CONSTANT nor a value of " + sel.name());
    e = coerce(std::move(e), sel, "a CASE label");
    ExecContext none;
    return e->eval(none).i;
}

StmtPtr Compiler::for_stmt(const ParseNode& n) {
    auto s = std::make_unique<For>();
    const ParseNode& id = *n.children.at(0);
    const Found f = lookup(id);
    if (!f.var->type.integer())
        fail(id, "type mismatch: the FOR variable '" + name_of(id) + "' must be an integer, not " + f.var->type.name());
    LValuePtr v = place(f, id);
    if (f.var->read_only) fail(id, "'" + v->name + "' is " + (f.var->constant ? "a CONSTANT" : "read-only"));
    const Type t = v->type;
    s->from = coerce(expr(*n.children.at(1)), t, "the start of FOR " + v->name);
    s->to = coerce(expr(*n.children.at(2)), t, "the end of FOR " + v->name);
    std::size_t body = 3;
    if (n.children.at(3)->is_type<g::for_by>()) {
        s->by = coerce(expr(*n.children[3]->children.at(0)), t, "the step of FOR " + v->name);
        body = 4;
    }
    s->var = std::move(v);
    ++loops_;
    s->body = statements(*n.children.at(body));
    --loops_;
    return s;
}

} // namespace rcsim::st::detail
