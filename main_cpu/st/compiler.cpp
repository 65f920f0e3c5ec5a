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
    case Kind::Byte: return to == Kind::Word || to == Kind::Dword;
    case Kind::Word: return to == Kind::Dword;
    default: return false;
    }
}

bool fits(Kind k, std::int64_t v) {
    switch (k) {
    case Kind::Int: return v >= -32768 && v <= 32767;
    case Kind::Dint: return v >= std::numeric_limits<std::int32_t>::min() && v <= std::numeric_limits<std::int32_t>::max();
    case Kind::Udint: case Kind::Dword: return v >= 0 && v <= 0xFFFFFFFFll;
    case Kind::Byte: return v >= 0 && v <= 0xFF;
    case Kind::Word: return v >= 0 && v <= 0xFFFF;
    default: return true;
    }
}

const std::map<std::string, Kind>& elementary_types() {
    static const std::map<std::string, Kind> m{{"BOOL", Kind::Bool},   {"INT", Kind::Int},   {"DINT", Kind::Dint},
                                               {"UDINT", Kind::Udint}, {"REAL", Kind::Real}, {"LREAL", Kind::Lreal},
                                               {"TIME", Kind::Time},   {"AXIS_REF", Kind::AxisRef},
                                               {"BYTE", Kind::Byte},   {"WORD", Kind::Word}, {"DWORD", Kind::Dword}};
    return m;
}

namespace {
/// IEC 61131-3's elementary types that the subset leaves out: named in their error.
bool unsupported_type(const std::string& upper_name) {
    static const char* const names[] = {"SINT", "USINT", "UINT", "LINT", "ULINT", "LWORD", "WSTRING", "CHAR",
                                        "WCHAR", "DATE", "TIME_OF_DAY", "TOD", "DATE_AND_TIME", "DT", "LTIME",
                                        "LDATE", "LTOD", "LDT", "LTIME_OF_DAY", "LDATE_AND_TIME"};
    for (const char* n : names)
        if (upper_name == n) return true;
    return false;
}
/// The default length of a STRING without [n] (CODESYS's; IEC leaves it to the implementation),
/// and the longest one accepted (a variable is a few hundred slots at most).
constexpr std::int64_t default_string_length = 80, max_string_length = 1024;
/// The most FB instances one POU may hold, nested ones included (each is a few dozen bytes).
constexpr std::size_t max_instances = 65536;
} // namespace

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
        if (n.is_type<g::type_block>()) {
            for (const auto& td : n.children) {
                const ParseNode& name = *td->children.at(0);
                const std::string key = upper(name_of(name));
                if (find_decl(key) || u_.type(key) || elementary_types().count(key) || type_decls_.count(key) ||
                    key == "STRING")
                    fail(name, "'" + name_of(name) + "' is already declared");
                type_decls_[key] = TypeDecl{td.get(), file, TypeDecl::State::declared, Type{}};
            }
            continue;
        }
        const ParseNode& name = *n.children.at(0);
        const std::string key = upper(name_of(name));
        if (find_decl(key) || u_.type(key) || elementary_types().count(key) || type_decls_.count(key))
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
        if (e.kind == Kind::Array || e.kind == Kind::AxisRef)
            fail(*n.children[2], "an ARRAY of " + e.name() + " is not supported (docs/st.md)");
        if (t.hi < t.lo) fail(n, "ARRAY[" + std::to_string(t.lo) + ".." + std::to_string(t.hi) + "] is empty");
        if (t.hi - t.lo >= 65536) fail(n, "ARRAY of more than 65536 elements");
        t.elem = e.kind;
        t.fb = e.fb;
        t.en = e.en;
        t.st = e.st;
        t.len = e.len;
        if (t.slots() > 65536) fail(n, "ARRAY of more than 65536 slots");
        return t;
    }
    if (n.is_type<g::string_type>()) {
        Type t{Kind::String};
        t.len = n.children.empty() ? default_string_length
                                   : integer_literal(trim(n.children[0]->string()), *n.children[0]);
        if (t.len < 1 || t.len > max_string_length)
            fail(n, "STRING[" + std::to_string(t.len) + "]: the length is 1 to " + std::to_string(max_string_length));
        return t;
    }
    const std::string key = upper(name_of(n));
    if (const auto it = elementary_types().find(key); it != elementary_types().end()) return Type::of(it->second);
    if (key == "STRING") {
        Type t{Kind::String};
        t.len = default_string_length;
        return t;
    }
    if (unsupported_type(key)) fail(n, key + " is not supported (docs/st.md)");
    if (key == "AXES_GROUP_REF")
        fail(n, "AXES_GROUP_REF is not supported: rcsim has no axes group object; the interpolating blocks take "
                "their group's axes as AxisX, AxisY (AxisZ, AxisU) inputs (docs/st.md \"Motion blocks\")");
    if (const auto it = type_decls_.find(key); it != type_decls_.end()) {
        const std::string_view keep = file_;
        PouType* keep_cur = cur_;
        const Type t = define_type(it->second, name_of(n));
        file_ = keep;
        cur_ = keep_cur;
        return t;
    }
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
                 : kind == "VAR_GLOBAL" ? VarKind::global : kind == "VAR_IN_OUT" ? VarKind::in_out : VarKind::local;
    const ParseNode& kw = *block.children[0];
    std::size_t first_decl = 1;
    bool constant = false;
    if (block.children.size() > 1 && block.children[1]->is_type<g::var_constant>()) {
        constant = true;
        first_decl = 2;
        if (vk != VarKind::local && vk != VarKind::global)
            fail(*block.children[1], kind + " CONSTANT: only VAR and VAR_GLOBAL may be CONSTANT");
    }
    if (vk == VarKind::in_out && where == PouType::Pou::program)
        fail(kw, "VAR_IN_OUT in a PROGRAM (nothing calls a PROGRAM to give it a variable)");
    if (where == PouType::Pou::globals && vk != VarKind::global)
        fail(kw, kind + " outside a PROGRAM, FUNCTION_BLOCK or FUNCTION (only VAR_GLOBAL is allowed here)");
    if (vk == VarKind::global && where != PouType::Pou::globals && where != PouType::Pou::program)
        fail(kw, "VAR_GLOBAL inside a " + std::string(where == PouType::Pou::function ? "FUNCTION" : "FUNCTION_BLOCK"));
    if (vk == VarKind::output && where == PouType::Pou::function)
        fail(kw, "VAR_OUTPUT in a FUNCTION is not in this subset (docs/st.md)");
    PouType& target = vk == VarKind::global ? u_.globals : p;
    for (std::size_t i = first_decl; i < block.children.size(); ++i) {
        const ParseNode& decl = *block.children[i];
        const ParseNode& names = *decl.children.at(0);
        const Type t = resolve_type(*decl.children.at(1));
        const ParseNode* init = decl.children.size() > 2 ? decl.children[2].get() : nullptr;
        if (vk == VarKind::global && t.kind == Kind::Fb && t.fb->pou != PouType::Pou::function_block)
            fail(*decl.children[1], "'" + t.name() + "' is not a function block");
        if (constant && !init) fail(names, "a CONSTANT needs its value: name : TYPE := value;");
        if (constant && (t.kind == Kind::Fb || t.fb_array())) fail(*decl.children[1], "a function block instance cannot be CONSTANT");
        if ((vk == VarKind::in_out || vk == VarKind::input || vk == VarKind::output) && t.fb_array())
            fail(*decl.children[1], "an ARRAY of function block instances as " + kind +
                                        " is not supported (docs/st.md); declare it in VAR");
        if (vk == VarKind::in_out && t.kind == Kind::Fb)
            fail(*decl.children[1], "a function block instance as VAR_IN_OUT is not supported (docs/st.md)");
        if (vk == VarKind::in_out && init) fail(*init, "a VAR_IN_OUT takes no initial value (it is the caller's variable)");
        for (const auto& nm : names.children) {
            add_var(target, name_of(*nm), *nm, t, vk, init);
            if (constant) {
                VarInfo& v = target.vars.back();
                v.constant = v.read_only = true;
            }
        }
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
    if (t.kind == Kind::Fb || t.fb_array()) {
        // An instance, or one per element of an ARRAY OF the block, in consecutive fb slots.
        if (init) v.fb_init = fb_initial_values(t, *init, name, &p);
        v.slot = p.fb_slots;
        const std::size_t n = t.kind == Kind::Fb ? 1 : static_cast<std::size_t>(t.hi - t.lo + 1);
        p.fb_slots += n;
        // Arrays of blocks holding arrays of blocks multiply: bound the instances one POU makes.
        p.instances += n * t.fb->instances;
        if (p.instances > max_instances)
            fail(at_node, "'" + p.name + "' would hold more than " + std::to_string(max_instances) +
                              " function block instances");
    } else if (kind == VarKind::in_out) {
        v.slot = p.ref_slots++;
    } else {
        v.slot = p.value_slots;
        p.value_slots += t.slots();
        v.init = init ? initial_values(t, *init, name, &p) : default_values(t);
    }
    p.index[key] = p.vars.size();
    p.vars.push_back(std::move(v));
}

std::vector<Value> Compiler::default_values(const Type& t) {
    switch (t.kind) {
    case Kind::AxisRef: return {Value{-1, 0}};
    case Kind::Enum: return {Value{t.en->init, 0}};
    case Kind::Struct: return t.st->init;
    case Kind::Array: {
        const std::vector<Value> one = default_values(t.element());
        std::vector<Value> all;
        all.reserve(t.slots());
        for (std::int64_t k = t.lo; k <= t.hi; ++k) all.insert(all.end(), one.begin(), one.end());
        return all;
    }
    default: return std::vector<Value>(t.slots());
    }
}

std::vector<Value> Compiler::initial_values(const Type& t, const ParseNode& init, const std::string& name,
                                            PouType* scope) {
    std::vector<Value> v = default_values(t);
    PouType* keep = cur_;
    const bool keep_only = constants_only_;
    cur_ = scope == &u_.globals ? nullptr : scope;
    constants_only_ = true; // initial values are constants (and the predefined axes)
    init_into(v, 0, t, *init.children.at(0), name);
    cur_ = keep;
    constants_only_ = keep_only;
    return v;
}

std::vector<std::vector<Value>> Compiler::fb_initial_values(const Type& t, const ParseNode& init,
                                                            const std::string& name, PouType* scope) {
    PouType* keep = cur_;
    const bool keep_only = constants_only_;
    cur_ = scope == &u_.globals ? nullptr : scope;
    constants_only_ = true;
    const ParseNode& value = *init.children.at(0);
    std::vector<std::vector<Value>> out;
    if (t.kind == Kind::Fb) {
        out.push_back(fb_inputs(*t.fb, value, name));
    } else {
        if (!value.is_type<g::array_init>())
            fail(value, "the initial value of an ARRAY of " + t.fb->name + " is a list: [(PT := T#1s), (PT := T#2s)]");
        const std::size_t n = static_cast<std::size_t>(t.hi - t.lo + 1);
        if (value.children.size() > n)
            fail(value, std::to_string(value.children.size()) + " initial values for " + std::to_string(n) +
                            " elements of '" + name + "'");
        for (std::size_t k = 0; k < value.children.size(); ++k)
            out.push_back(fb_inputs(*t.fb, *value.children[k], name + "[" + std::to_string(t.lo + k) + "]"));
    }
    cur_ = keep;
    constants_only_ = keep_only;
    return out;
}

std::vector<Value> Compiler::fb_inputs(const PouType& fb, const ParseNode& value, const std::string& name) {
    if (!value.is_type<g::struct_init>())
        fail(value, "the initial value of a " + fb.name + " instance names its inputs: (PT := T#1s)");
    std::vector<Value> out(fb.value_slots);
    for (const VarInfo& v : fb.vars)
        for (std::size_t k = 0; k < v.init.size(); ++k) out[v.slot + k] = v.init[k];
    for (const auto& mi : value.children) {
        const ParseNode& mn = *mi->children.at(0);
        const VarInfo* v = fb.find(upper(name_of(mn)));
        if (!v || v->kind != VarKind::input || v->type.kind == Kind::Fb)
            fail(mn, "'" + name_of(mn) + "' is not an input of " + fb.name);
        init_into(out, v->slot, v->type, *mi->children.at(1), name + "." + v->name);
    }
    return out;
}

void Compiler::init_into(std::vector<Value>& out, std::size_t at, const Type& t, const ParseNode& value,
                         const std::string& name) {
    if (value.is_type<g::array_init>()) {
        if (t.kind != Kind::Array) fail(value, "'" + name + "' is " + t.name() + ", not an ARRAY");
        const std::size_t n = static_cast<std::size_t>(t.hi - t.lo + 1), stride = t.element().slots();
        if (value.children.size() > n)
            fail(value, std::to_string(value.children.size()) + " initial values for " + std::to_string(n) +
                            " elements of '" + name + "'");
        for (std::size_t k = 0; k < value.children.size(); ++k)
            init_into(out, at + k * stride, t.element(), *value.children[k], name);
        return;
    }
    if (value.is_type<g::struct_init>()) {
        if (t.kind != Kind::Struct) fail(value, "'" + name + "' is " + t.name() + ", not a STRUCT");
        for (const auto& mi : value.children) {
            const ParseNode& mn = *mi->children.at(0);
            const StructType::Member* m = t.st->find(upper(name_of(mn)));
            if (!m) fail(mn, "'" + name_of(mn) + "' is not a member of " + t.name());
            init_into(out, at + m->offset, m->type, *mi->children.at(1), name + "." + m->name);
        }
        return;
    }
    if (t.kind == Kind::Array) fail(value, "an ARRAY's initial value is a list: [1, 2, 3]");
    if (t.kind == Kind::Struct) fail(value, "a STRUCT's initial value names its members: (x := 1, y := 2)");
    ExprPtr x = coerce(expr(value), t, "the initial value of '" + name + "'");
    if (!x->constant()) {
        // An AXIS_REF may start as one of the predefined axes (read-only globals with a fixed value).
        if (const auto* r = dynamic_cast<const LValue*>(x.get());
            r && r->base == LValue::Base::global && r->read_only && t.kind == Kind::AxisRef) {
            out[at] = u_.globals.vars[u_.globals.index.at(upper(r->name))].init.at(0);
            return;
        }
        fail(value, "the initial value of '" + name + "' must be a constant");
    }
    ExecContext none;
    if (t.kind == Kind::String) pack(&out[at], t.len, x->text(none));
    else out[at] = normalise(t.kind, x->eval(none));
}

// ---- TYPE ... END_TYPE (§6.4.4) ----------------------------------------------------------------

Type Compiler::define_type(TypeDecl& d, const std::string& name) {
    if (d.state == TypeDecl::State::defined) return d.type;
    if (d.state == TypeDecl::State::defining) fail(*d.node, "type '" + name + "' contains itself");
    d.state = TypeDecl::State::defining;
    file_ = d.file;
    const ParseNode& n = *d.node;
    const std::string tname = name_of(*n.children.at(0));
    const ParseNode& def = *n.children.at(1);
    const ParseNode* init = n.children.size() > 2 ? n.children[2].get() : nullptr;
    if (def.is_type<g::enum_spec>()) {
        d.type = define_enum(def, tname, init);
    } else {
        if (init) fail(*init, "an initial value in a TYPE declaration is only for an enumeration here");
        if (def.is_type<g::struct_spec>()) {
            d.type = define_struct(def, tname);
        } else {
            d.type = resolve_type(def); // an alias: TYPE Speed : LREAL; END_TYPE
            if (d.type.kind == Kind::Fb || d.type.fb_array()) fail(def, "a TYPE cannot name a function block");
        }
    }
    d.state = TypeDecl::State::defined;
    return d.type;
}

Type Compiler::define_enum(const ParseNode& spec, const std::string& name, const ParseNode* init) {
    auto e = std::make_unique<EnumType>();
    e->name = name;
    std::int64_t next = 0;
    for (const auto& item : spec.children) {
        const ParseNode& id = *item->children.at(0);
        for (const auto& [other, x] : e->values)
            if (upper(other) == upper(name_of(id))) fail(id, "'" + name_of(id) + "' is already a value of " + name);
        if (try_lookup(upper(name_of(id))).var)
            fail(id, "'" + name_of(id) + "' is already a variable");
        if (item->children.size() > 1) next = integer_literal(trim(item->children[1]->string()), *item->children[1]);
        if (!fits(Kind::Dint, next)) fail(*item, "the value of '" + name_of(id) + "' does not fit in DINT");
        e->values.emplace_back(name_of(id), next);
        ++next;
    }
    e->init = e->values.front().second;
    u_.enums.push_back(std::move(e));
    Type t{Kind::Enum};
    t.en = u_.enums.back().get();
    if (init) {
        const std::vector<Value> v = initial_values(t, *init, name, nullptr);
        u_.enums.back()->init = v.at(0).i;
    }
    return t;
}

Type Compiler::define_struct(const ParseNode& spec, const std::string& name) {
    auto st = std::make_unique<StructType>();
    st->name = name;
    StructType* sp = st.get();
    u_.structs.push_back(std::move(st));
    for (const auto& decl : spec.children) {
        const Type t = resolve_type(*decl->children.at(1));
        if (t.kind == Kind::Fb || t.fb_array()) fail(*decl->children[1], "a function block instance in a STRUCT is not supported (docs/st.md)");
        const ParseNode* init = decl->children.size() > 2 ? decl->children[2].get() : nullptr;
        for (const auto& nm : decl->children.at(0)->children) {
            if (sp->find(upper(name_of(*nm)))) fail(*nm, "'" + name_of(*nm) + "' is declared twice");
            StructType::Member m{name_of(*nm), t, sp->slots};
            const std::vector<Value> v = init ? initial_values(t, *init, m.name, nullptr) : default_values(t);
            sp->init.insert(sp->init.end(), v.begin(), v.end());
            sp->slots += t.slots();
            sp->members.push_back(std::move(m));
        }
    }
    if (sp->slots > 65536) fail(spec, "STRUCT " + name + " of more than 65536 slots");
    Type t{Kind::Struct};
    t.st = sp;
    return t;
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
    // Every TYPE, used or not (an enumeration's values are names the program may use).
    for (auto& [key, td] : type_decls_) define_type(td, name_of(*td.node->children.at(0)));
    for (const auto& [block, file] : global_blocks_) {
        file_ = file;
        add_vars(u_.globals, *block, PouType::Pou::globals);
    }
    for (auto& [key, d] : decls_) layout(d);
    for (auto& [key, d] : decls_) compile_body(d);
}

Compiler::Found Compiler::try_lookup(const std::string& key) const {
    if (cur_)
        if (const VarInfo* v = cur_->find(key)) return {v, false};
    if (const VarInfo* v = u_.globals.find(key)) return {v, true};
    return {};
}

Compiler::Found Compiler::lookup(const ParseNode& n) {
    const Found f = try_lookup(upper(name_of(n)));
    if (f.var && constants_only_ && !f.var->read_only) fail(n, "'" + name_of(n) + "' is not a constant");
    if (f.var) return f;
    if (constants_only_) fail(n, "'" + name_of(n) + "' is not a constant");
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
    add_manual_motion_blocks(*u);
    detail::Compiler c(*u);
    c.add_source(standard_prelude(), "<standard library>");
    c.add_source(text, file);
    c.finish();
    return u;
}

} // namespace rcsim::st
