// rcsim — the Structured Text compiler. See compiler.h; the subset is docs/st.md.
#include "main_cpu/st/compiler.h"

#include "main_cpu/st/compiler_impl.h"

#include "main_cpu/st/grammar.h"
#include "main_cpu/st/library.h"
#include "main_cpu/st/parser.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

namespace rcsim::st {

std::string upper(std::string s) {
    for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return s;
}

const PouType* Unit::type(const std::string& n) const {
    for (const auto& p : pous)
        if (upper(p->name) == n) return p.get();
    return nullptr;
}

namespace detail {

namespace g = grammar;

std::string trim(std::string s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    return s;
}

std::string strip_underscores(std::string s) {
    s.erase(std::remove(s.begin(), s.end(), '_'), s.end());
    return s;
}

bool widens(Kind from, Kind to) {
    switch (from) {
    case Kind::Int: return to == Kind::Dint || to == Kind::Real || to == Kind::Lreal;
    case Kind::Dint: case Kind::Udint: return to == Kind::Lreal;
    case Kind::Real: return to == Kind::Lreal;
    default: return false;
    }
}

bool fits(Kind k, std::int64_t v) {
    switch (k) {
    case Kind::Int: return v >= -32768 && v <= 32767;
    case Kind::Dint: return v >= std::numeric_limits<std::int32_t>::min() && v <= std::numeric_limits<std::int32_t>::max();
    case Kind::Udint: return v >= 0 && v <= 0xFFFFFFFFll;
    default: return true;
    }
}

const std::map<std::string, Kind>& elementary_types() {
    static const std::map<std::string, Kind> m{{"BOOL", Kind::Bool},   {"INT", Kind::Int},   {"DINT", Kind::Dint},
                                               {"UDINT", Kind::Udint}, {"REAL", Kind::Real}, {"LREAL", Kind::Lreal},
                                               {"TIME", Kind::Time},   {"AXIS_REF", Kind::AxisRef}};
    return m;
}

// ---- declarations --------------------------------------------------------------------------------

void Compiler::add_source(const std::string& text, const std::string& file) {
    u_.texts.push_back(text);
    u_.files.push_back(file);
    trees_.push_back(parse(u_.texts.back(), u_.files.back()));
    declare(*trees_.back(), u_.files.back());
}

Compiler::Decl* Compiler::find_decl(const std::string& n) {
    const auto it = decls_.find(n);
    return it == decls_.end() ? nullptr : &it->second;
}

void Compiler::declare(const ParseNode& root, std::string_view file) {
    file_ = file;
    for (const auto& child : root.children) {
        const ParseNode& n = *child;
        if (n.is_type<g::var_block>()) {
            global_blocks_.emplace_back(&n, file);
            continue;
        }
        const ParseNode& name = *n.children.at(0);
        const std::string key = upper(name_of(name));
        if (find_decl(key) || u_.type(key) || elementary_types().count(key))
            fail(name, "'" + name_of(name) + "' is already declared");
        auto pou = std::make_unique<PouType>();
        pou->name = name_of(name);
        pou->pou = n.is_type<g::program>()          ? PouType::Pou::program
                   : n.is_type<g::function_block>() ? PouType::Pou::function_block
                                                    : PouType::Pou::function;
        Decl d;
        d.node = &n;
        d.pou = pou.get();
        d.file = file;
        u_.pous.push_back(std::move(pou));
        decls_.emplace(key, std::move(d));
        if (u_.pous.back()->pou == PouType::Pou::program) {
            u_.programs[key] = u_.pous.back().get();
            u_.program_names.push_back(u_.pous.back()->name);
        }
    }
}

Type Compiler::resolve_type(const ParseNode& n) {
    if (n.is_type<g::array_type>()) {
        Type t;
        t.kind = Kind::Array;
        t.lo = integer_literal(trim(n.children.at(0)->string()), *n.children[0]);
        t.hi = integer_literal(trim(n.children.at(1)->string()), *n.children[1]);
        const Type e = resolve_type(*n.children.at(2));
        if (!e.elementary()) fail(*n.children[2], "ARRAY elements must be of an elementary type, not " + e.name());
        if (t.hi < t.lo) fail(n, "ARRAY[" + std::to_string(t.lo) + ".." + std::to_string(t.hi) + "] is empty");
        if (t.hi - t.lo >= 65536) fail(n, "ARRAY of more than 65536 elements");
        t.elem = e.kind;
        return t;
    }
    const std::string key = upper(name_of(n));
    if (const auto it = elementary_types().find(key); it != elementary_types().end()) return Type::of(it->second);
    if (Decl* d = find_decl(key)) {
        if (d->pou->pou != PouType::Pou::function_block) fail(n, "'" + name_of(n) + "' is not a type");
        if (d->state == Decl::State::laying_out)
            fail(n, "function block '" + name_of(n) + "' contains an instance of itself");
        const std::string_view keep = file_;
        layout(*d);
        file_ = keep;
        Type t{Kind::Fb};
        t.fb = d->pou;
        return t;
    }
    if (const PouType* p = u_.type(key); p && p->pou == PouType::Pou::function_block) {
        Type t{Kind::Fb};
        t.fb = p;
        return t;
    }
    fail(n, "unknown type '" + name_of(n) + "'");
}

void Compiler::layout(Decl& d) {
    if (d.state != Decl::State::declared) return;
    d.state = Decl::State::laying_out;
    file_ = d.file;
    PouType& p = *d.pou;
    const ParseNode& n = *d.node;
    std::size_t first_block = 1;
    if (p.pou == PouType::Pou::function) {
        p.result = resolve_type(*n.children.at(1));
        if (!p.result.elementary()) fail(*n.children[1], "a FUNCTION returns an elementary type, not " + p.result.name());
        add_var(p, p.name, *n.children[0], p.result, VarKind::local, nullptr);
        first_block = 2;
    }
    for (std::size_t i = first_block; i < n.children.size(); ++i)
        if (n.children[i]->is_type<g::var_block>()) add_vars(p, *n.children[i], p.pou);
    d.state = Decl::State::laid_out;
}

void Compiler::add_vars(PouType& p, const ParseNode& block, PouType::Pou where) {
    const std::string kind = upper(trim(block.children.at(0)->string()));
    VarKind vk = kind == "VAR_INPUT" ? VarKind::input : kind == "VAR_OUTPUT" ? VarKind::output
                 : kind == "VAR_GLOBAL" ? VarKind::global : VarKind::local;
    const ParseNode& kw = *block.children[0];
    if (where == PouType::Pou::globals && vk != VarKind::global)
        fail(kw, kind + " outside a PROGRAM, FUNCTION_BLOCK or FUNCTION (only VAR_GLOBAL is allowed here)");
    if (vk == VarKind::global && where != PouType::Pou::globals && where != PouType::Pou::program)
        fail(kw, "VAR_GLOBAL inside a " + std::string(where == PouType::Pou::function ? "FUNCTION" : "FUNCTION_BLOCK"));
    if (vk == VarKind::output && where == PouType::Pou::function)
        fail(kw, "VAR_OUTPUT in a FUNCTION is not in this subset (docs/st.md)");
    PouType& target = vk == VarKind::global ? u_.globals : p;
    for (std::size_t i = 1; i < block.children.size(); ++i) {
        const ParseNode& decl = *block.children[i];
        const ParseNode& names = *decl.children.at(0);
        const Type t = resolve_type(*decl.children.at(1));
        const ParseNode* init = decl.children.size() > 2 ? decl.children[2].get() : nullptr;
        if (vk == VarKind::global && t.kind == Kind::Fb && t.fb->pou != PouType::Pou::function_block)
            fail(*decl.children[1], "'" + t.name() + "' is not a function block");
        for (const auto& nm : names.children) add_var(target, name_of(*nm), *nm, t, vk, init);
    }
}

void Compiler::add_var(PouType& p, const std::string& name, const ParseNode& at_node, Type t, VarKind kind,
                       const ParseNode* init) {
    const std::string key = upper(name);
    if (p.find(key)) fail(at_node, "'" + name + "' is declared twice");
    if (elementary_types().count(key)) fail(at_node, "'" + name + "' is a type name");
    VarInfo v;
    v.name = name;
    v.type = t;
    v.kind = kind;
    v.pos = at(at_node);
    if (t.kind == Kind::Fb) {
        if (init) fail(*init, "a function block instance takes no initial value");
        v.slot = p.fb_slots++;
    } else {
        v.slot = p.value_slots;
        p.value_slots += t.slots();
        v.init = init ? initial_values(t, *init, name) : std::vector<Value>(t.slots());
        if (t.kind == Kind::AxisRef && !init) v.init.assign(1, Value{-1, 0});
    }
    p.index[key] = p.vars.size();
    p.vars.push_back(std::move(v));
}

std::vector<Value> Compiler::initial_values(const Type& t, const ParseNode& init, const std::string& name) {
    const ParseNode& value = *init.children.at(0);
    auto one = [&](const ParseNode& e, const Type& to) {
        PouType* keep = cur_;
        cur_ = nullptr; // initial values are constants: no variables (the axes are globals)
        ExprPtr x = coerce(expr(e), to, "the initial value of '" + name + "'");
        cur_ = keep;
        // An AXIS_REF may start as one of the predefined axes (read-only globals with a fixed value).
        if (const auto* r = dynamic_cast<const VarRef*>(x.get()); r && r->global && r->read_only)
            return u_.globals.vars[u_.globals.index.at(upper(r->name))].init.at(0);
        if (!x->constant()) fail(e, "the initial value of '" + name + "' must be a constant");
        ExecContext none;
        return normalise(to.kind, x->eval(none));
    };
    if (value.is_type<g::array_init>()) {
        if (t.kind != Kind::Array) fail(value, "'" + name + "' is " + t.name() + ", not an ARRAY");
        if (value.children.size() > t.slots())
            fail(value, std::to_string(value.children.size()) + " initial values for " + std::to_string(t.slots()) +
                            " elements of '" + name + "'");
        std::vector<Value> v(t.slots());
        for (std::size_t k = 0; k < value.children.size(); ++k) v[k] = one(*value.children[k], Type::of(t.elem));
        return v;
    }
    if (t.kind == Kind::Array) fail(value, "an ARRAY's initial value is a list: [1, 2, 3]");
    return {one(value, t)};
}

void Compiler::compile_body(Decl& d) {
    if (d.state == Decl::State::compiled) return;
    if (d.state == Decl::State::compiling) return; // a FB body refers to itself only through instances
    layout(d);
    d.state = Decl::State::compiling;
    PouType* keep_cur = cur_;
    const std::string_view keep_file = file_;
    const int keep_loops = loops_;
    cur_ = d.pou;
    file_ = d.file;
    loops_ = 0;
    for (const auto& c : d.node->children)
        if (c->is_type<g::statements>()) d.pou->body = statements(*c);
    d.state = Decl::State::compiled;
    cur_ = keep_cur;
    file_ = keep_file;
    loops_ = keep_loops;
}

void Compiler::finish() {
    for (const auto& [block, file] : global_blocks_) {
        file_ = file;
        add_vars(u_.globals, *block, PouType::Pou::globals);
    }
    for (auto& [key, d] : decls_) layout(d);
    for (auto& [key, d] : decls_) compile_body(d);
}

Compiler::Found Compiler::lookup(const ParseNode& n) {
    const std::string key = upper(name_of(n));
    if (cur_)
        if (const VarInfo* v = cur_->find(key)) return {v, false};
    if (const VarInfo* v = u_.globals.find(key)) return {v, true};
    if (!cur_) fail(n, "'" + name_of(n) + "' is not a constant");
    fail(n, "unknown identifier '" + name_of(n) + "'");
}

} // namespace detail

std::unique_ptr<Unit> compile(const std::string& text, const std::string& file, unsigned axes) {
    auto u = std::make_unique<Unit>();
    u->globals.pou = PouType::Pou::globals;
    u->globals.name = "globals";
    PouBuilder gb{u->globals};
    for (unsigned a = 0; a < axes; ++a) {
        const std::size_t slot = gb.add("Axis" + std::to_string(a), VarKind::global, Kind::AxisRef, Value{a, 0});
        u->globals.vars[u->globals.index.at(upper("Axis" + std::to_string(a)))].read_only = true;
        (void)slot;
    }
    add_timer_blocks(*u);
    add_motion_blocks(*u);
    detail::Compiler c(*u);
    c.add_source(standard_prelude(), "<standard library>");
    c.add_source(text, file);
    c.finish();
    return u;
}

} // namespace rcsim::st
