// rcsim — execution of the compiled Structured Text tree. See ast.h.
#include "main_cpu/st/ast.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

namespace rcsim::st {

const char* kind_name(Kind k) {
    switch (k) {
    case Kind::Void: return "VOID";
    case Kind::Bool: return "BOOL";
    case Kind::Int: return "INT";
    case Kind::Dint: return "DINT";
    case Kind::Udint: return "UDINT";
    case Kind::Real: return "REAL";
    case Kind::Lreal: return "LREAL";
    case Kind::Time: return "TIME";
    case Kind::AxisRef: return "AXIS_REF";
    case Kind::Fb: return "FUNCTION_BLOCK";
    case Kind::Array: return "ARRAY";
    case Kind::Byte: return "BYTE";
    case Kind::Word: return "WORD";
    case Kind::Dword: return "DWORD";
    case Kind::String: return "STRING";
    case Kind::Enum: return "an enumeration";
    case Kind::Struct: return "a STRUCT";
    }
    return "?";
}

std::string Type::name() const {
    if (kind == Kind::Fb && fb) return fb->name;
    if (kind == Kind::Enum && en) return en->name;
    if (kind == Kind::Struct && st) return st->name;
    if (kind == Kind::String) return "STRING[" + std::to_string(len) + "]";
    if (kind == Kind::Array)
        return "ARRAY[" + std::to_string(lo) + ".." + std::to_string(hi) + "] OF " + element().name();
    return kind_name(kind);
}

std::size_t Type::slots() const {
    switch (kind) {
    case Kind::Array: return static_cast<std::size_t>(hi - lo + 1) * element().slots();
    case Kind::String: return string_slots(len);
    case Kind::Struct: return st ? st->slots : 0;
    default: return 1;
    }
}

std::string EnumType::value_name(std::int64_t v) const {
    for (const auto& [n, x] : values)
        if (x == v) return n;
    return "";
}

const StructType::Member* StructType::find(const std::string& upper_name) const {
    for (const Member& m : members) {
        std::string u = m.name;
        for (char& ch : u) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
        if (u == upper_name) return &m;
    }
    return nullptr;
}

std::size_t string_slots(std::int64_t n) { return 1 + static_cast<std::size_t>((n + 7) / 8); }

void pack(Value* slots, std::int64_t n, const std::string& text) {
    const std::size_t len = std::min(text.size(), static_cast<std::size_t>(n));
    slots[0].i = static_cast<std::int64_t>(len);
    for (std::size_t k = 0; k < static_cast<std::size_t>((n + 7) / 8); ++k) {
        std::uint64_t w = 0;
        for (std::size_t b = 0; b < 8 && 8 * k + b < len; ++b)
            w |= static_cast<std::uint64_t>(static_cast<unsigned char>(text[8 * k + b])) << (8 * b);
        slots[1 + k].i = static_cast<std::int64_t>(w);
    }
}

std::string unpack(const Value* slots) {
    const auto len = static_cast<std::size_t>(slots[0].i);
    std::string s(len, '\0');
    for (std::size_t k = 0; k < len; ++k)
        s[k] = static_cast<char>(static_cast<std::uint64_t>(slots[1 + k / 8].i) >> (8 * (k % 8)));
    return s;
}

std::int64_t wrap(Kind k, std::int64_t v) {
    switch (k) {
    case Kind::Int: return static_cast<std::int16_t>(static_cast<std::uint16_t>(v));
    case Kind::Dint: return static_cast<std::int32_t>(static_cast<std::uint32_t>(v));
    case Kind::Udint: return static_cast<std::uint32_t>(v);
    case Kind::Bool: return v != 0;
    case Kind::Byte: return static_cast<std::uint8_t>(v);
    case Kind::Word: return static_cast<std::uint16_t>(v);
    case Kind::Dword: return static_cast<std::uint32_t>(v);
    default: return v;
    }
}

Value normalise(Kind k, Value v) {
    if (k == Kind::Real) v.r = static_cast<float>(v.r);
    else if (k != Kind::Lreal) v.i = wrap(k, v.i);
    return v;
}

void ExecContext::tick(const SourcePos& at) {
    if (++executed > budget)
        throw RuntimeError(at.str() + ": more than " + std::to_string(budget) +
                           " statements in one cycle (an endless loop?); the program is stopped");
}

std::unique_ptr<Instance> PouType::instantiate() const {
    auto inst = std::make_unique<Instance>();
    inst->type = this;
    inst->vars.resize(value_slots);
    inst->fbs.resize(fb_slots);
    for (const VarInfo& v : vars) {
        if (v.type.kind == Kind::Fb || v.type.fb_array()) {
            const std::size_t n = v.type.kind == Kind::Fb ? 1 : static_cast<std::size_t>(v.type.hi - v.type.lo + 1);
            for (std::size_t k = 0; k < n; ++k) {
                inst->fbs[v.slot + k] = v.type.fb->instantiate();
                if (k < v.fb_init.size() && !v.fb_init[k].empty()) inst->fbs[v.slot + k]->vars = v.fb_init[k];
            }
            continue;
        }
        for (std::size_t k = 0; k < v.init.size(); ++k) inst->vars[v.slot + k] = v.init[k];
    }
    inst->refs.assign(ref_slots, nullptr);
    if (native) inst->native = native();
    return inst;
}

// ---- expressions ---------------------------------------------------------------------------------

Instance* InstancePath::get(ExecContext& c) const {
    Instance* owner = global ? c.globals : c.self;
    if (!index) return owner->fbs[slot].get();
    const std::int64_t i = index->eval(c).i;
    if (i < lo || i > hi)
        throw RuntimeError(pos.str() + ": index " + std::to_string(i) + " outside " + name + "[" + std::to_string(lo) +
                           ".." + std::to_string(hi) + "]");
    return owner->fbs[slot + static_cast<std::size_t>(i - lo)].get();
}

Value* LValue::first(ExecContext& c) const {
    Value* p = nullptr;
    switch (base) {
    case Base::self: p = &c.self->vars[slot]; break;
    case Base::global: p = &c.globals->vars[slot]; break;
    case Base::fb_member: p = &inst.get(c)->vars[slot]; break;
    case Base::in_out: p = c.self->refs[slot]; break;
    }
    p += offset;
    for (const Index& x : indices) {
        const std::int64_t i = x.index->eval(c).i;
        if (i < x.lo || i > x.hi)
            throw RuntimeError(pos.str() + ": index " + std::to_string(i) + " outside " + name + "[" +
                               std::to_string(x.lo) + ".." + std::to_string(x.hi) + "]");
        p += static_cast<std::size_t>(i - x.lo) * x.stride;
    }
    return p;
}

void copy_datum(Value* dst, const Type& to, const Value* src, const Type& from) {
    if (to.kind == Kind::String) pack(dst, to.len, unpack(src));
    else if (to.elementary()) {
        Value v = *src;
        if (to.real() && !from.real()) v.r = static_cast<double>(v.i); // a widening INT -> REAL output
        *dst = normalise(to.kind, v);
    }
    else std::copy_n(src, std::min(to.slots(), from.slots()), dst);
}

void store(Value* dst, const Type& t, const Expr& e, ExecContext& c) {
    if (t.kind == Kind::String) {
        pack(dst, t.len, e.text(c));
    } else if (t.elementary()) {
        *dst = normalise(t.kind, e.eval(c));
    } else {
        // A STRUCT or ARRAY: the compiler only lets a variable of the same type be the value.
        const Value* src = static_cast<const LValue&>(e).first(c);
        if (src != dst) std::copy_n(src, t.slots(), dst);
    }
}

Value Unary::eval(ExecContext& c) const {
    Value v = a->eval(c);
    if (op == Op::not_) v.i = type.bits() ? ~v.i : !v.i;
    else if (type.real()) v.r = -v.r;
    else v.i = static_cast<std::int64_t>(0 - static_cast<std::uint64_t>(v.i));
    return normalise(type.kind, v);
}

namespace {

Value boolean(bool b) { return Value{b ? 1 : 0, 0}; }

template <typename T> Value compare(Op op, T x, T y) {
    switch (op) {
    case Op::lt: return boolean(x < y);
    case Op::le: return boolean(x <= y);
    case Op::gt: return boolean(x > y);
    case Op::ge: return boolean(x >= y);
    case Op::eq: return boolean(x == y);
    default: return boolean(x != y);
    }
}

bool is_comparison(Op op) { return op >= Op::lt && op <= Op::ne; }

Value real_op(Op op, Kind k, double x, double y, const SourcePos& at) {
    Value v;
    switch (op) {
    case Op::add: v.r = x + y; break;
    case Op::sub: v.r = x - y; break;
    case Op::mul: v.r = x * y; break;
    case Op::div:
        if (y == 0) throw RuntimeError(at.str() + ": division by zero");
        v.r = x / y;
        break;
    case Op::pow: v.r = std::pow(x, y); break;
    default: return compare(op, x, y);
    }
    return normalise(k, v);
}

/// Integer and TIME arithmetic in 64-bit unsigned (defined wrap), then to the type's width.
Value int_op(Op op, Kind k, std::int64_t x, std::int64_t y, const SourcePos& at) {
    const auto ux = static_cast<std::uint64_t>(x), uy = static_cast<std::uint64_t>(y);
    Value v;
    switch (op) {
    case Op::add: v.i = static_cast<std::int64_t>(ux + uy); break;
    case Op::sub: v.i = static_cast<std::int64_t>(ux - uy); break;
    case Op::mul: v.i = static_cast<std::int64_t>(ux * uy); break;
    case Op::div:
    case Op::mod:
        if (y == 0) throw RuntimeError(at.str() + (op == Op::div ? ": division by zero" : ": MOD by zero"));
        if (x == std::numeric_limits<std::int64_t>::min() && y == -1) v.i = op == Op::div ? x : 0;
        else v.i = op == Op::div ? x / y : x % y; // both truncate towards zero (IEC: sign of the dividend)
        break;
    // On BOOL (0 or 1) and on the bit strings alike: bit by bit (IEC 61131-3 Table 28).
    case Op::and_: v.i = x & y; break;
    case Op::or_: v.i = x | y; break;
    case Op::xor_: v.i = x ^ y; break;
    default: return compare(op, x, y);
    }
    v.i = wrap(k, v.i);
    return v;
}

} // namespace

Value Binary::eval(ExecContext& c) const {
    // AND and OR do not evaluate the right operand when the left decides (as CODESYS does; IEC
    // leaves the order open, and the operands here have no side effects but errors).
    const Value x = a->eval(c);
    if (operand.kind == Kind::Bool && op == Op::and_ && !x.i) return boolean(false);
    if (operand.kind == Kind::Bool && op == Op::or_ && x.i) return boolean(true);
    const Value y = b->eval(c);
    if (type.kind == Kind::Time && operand.kind != Kind::Time) {
        // TIME * number, TIME / number: the number is b, converted to LREAL by the compiler.
        const double t = static_cast<double>(x.i);
        if (op == Op::div && y.r == 0) throw RuntimeError(pos.str() + ": division by zero");
        return Value{std::llround(op == Op::mul ? t * y.r : t / y.r), 0};
    }
    if (operand.real()) return real_op(op, is_comparison(op) ? Kind::Bool : type.kind, x.r, y.r, pos);
    return int_op(op, is_comparison(op) ? Kind::Bool : operand.kind, x.i, y.i, pos);
}

namespace {
std::int64_t to_integer(double r, const Type& to, const SourcePos& at) {
    if (!std::isfinite(r) || std::fabs(r) > 9.2e18)
        throw RuntimeError(at.str() + ": " + std::to_string(r) + " does not fit in " + to.name());
    return static_cast<std::int64_t>(r);
}
} // namespace

Value Convert::eval(ExecContext& c) const {
    // TIME converts as milliseconds (TIME_TO_DINT(T#1s) = 1000, as in CODESYS); it is kept in
    // microseconds. REAL to integer rounds to nearest (IEC 61131-3 §6.6.2.5.6), TRUNC cuts.
    const Value v = a->eval(c);
    const Type& from = a->type;
    Value out;
    if (type.real()) {
        out.r = from.kind == Kind::Time ? static_cast<double>(v.i) / 1000.0 : from.real() ? v.r : static_cast<double>(v.i);
    } else if (type.kind == Kind::Time) {
        const double ms = from.real() ? v.r : static_cast<double>(v.i);
        out.i = to_integer(truncate ? std::trunc(ms * 1000.0) : std::round(ms * 1000.0), type, pos);
    } else if (from.kind == Kind::Time) {
        out.i = v.i / 1000;
    } else if (from.real()) {
        out.i = type.kind == Kind::Bool ? v.r != 0 : to_integer(truncate ? std::trunc(v.r) : std::round(v.r), type, pos);
    } else {
        out.i = v.i;
    }
    return normalise(type.kind, out);
}

Value Builtin::eval(ExecContext& c) const {
    std::vector<Value> v;
    v.reserve(args.size());
    for (const ExprPtr& e : args) v.push_back(e->eval(c));
    return normalise(type.kind, fn(type, v, pos));
}

Value StringCompare::eval(ExecContext& c) const {
    return compare(op, a->text(c), b->text(c));
}

std::string StringFn::text(ExecContext& c) const {
    std::vector<std::string> s;
    std::vector<std::int64_t> n;
    for (const ExprPtr& e : args) {
        if (e->type.kind == Kind::String) s.push_back(e->text(c));
        else n.push_back(e->eval(c).i);
    }
    std::string out = fn(s, n, pos);
    if (out.size() > static_cast<std::size_t>(type.len)) out.resize(static_cast<std::size_t>(type.len));
    return out;
}

Value StringInt::eval(ExecContext& c) const {
    std::vector<std::string> s;
    for (const ExprPtr& e : args) s.push_back(e->text(c));
    return Value{fn(s), 0};
}

const Expr& Select::chosen(ExecContext& c) const {
    const std::int64_t k = selector->eval(c).i;
    if (k < 0 || k >= static_cast<std::int64_t>(inputs.size()))
        throw RuntimeError(pos.str() + ": MUX selector K = " + std::to_string(k) + " outside 0.." +
                           std::to_string(inputs.size() - 1));
    return *inputs[static_cast<std::size_t>(k)];
}

Value FunctionCall::eval(ExecContext& c) const {
    std::unique_ptr<Instance> inst = fn->instantiate();
    for (const auto& [v, e] : inputs) store(&inst->vars[v->slot], v->type, *e, c);
    for (const auto& [ref, var] : in_outs) inst->refs[ref] = var->first(c);
    run_pou(*inst, c);
    return inst->vars[result_slot];
}

// ---- statements ----------------------------------------------------------------------------------

Flow run_block(const Block& b, ExecContext& c) {
    for (const StmtPtr& s : b) {
        c.tick(s->pos);
        const Flow f = s->exec(c);
        if (f != Flow::normal) return f;
    }
    return Flow::normal;
}

void run_pou(Instance& inst, ExecContext& c) {
    Instance* caller = c.self;
    c.self = &inst;
    try {
        if (inst.native) inst.native->call(inst, c);
        else run_block(inst.type->body, c);
    } catch (...) {
        c.self = caller;
        throw;
    }
    c.self = caller;
}

Flow Assign::exec(ExecContext& c) const {
    if (target->type.elementary()) {
        // The value first: evaluating it may fail, and the target's index is checked after it.
        const Value v = normalise(target->type.kind, value->eval(c));
        target->ref(c) = v;
    } else {
        store(target->first(c), target->type, *value, c);
    }
    return Flow::normal;
}

Flow FbCall::exec(ExecContext& c) const {
    Instance* i = inst.get(c);
    for (const auto& [v, e] : inputs) store(&i->vars[v->slot], v->type, *e, c);
    for (const auto& [ref, var] : in_outs) i->refs[ref] = var->first(c);
    run_pou(*i, c);
    for (const auto& [v, dest] : outputs) copy_datum(dest->first(c), dest->type, &i->vars[v->slot], v->type);
    return Flow::normal;
}

Flow If::exec(ExecContext& c) const {
    for (const auto& [cond, body] : branches)
        if (cond->eval(c).i) return run_block(body, c);
    return run_block(otherwise, c);
}

Flow Case::exec(ExecContext& c) const {
    const std::int64_t s = selector->eval(c).i;
    for (const Element& e : elements)
        for (const auto& [lo, hi] : e.ranges)
            if (s >= lo && s <= hi) return run_block(e.body, c);
    return run_block(otherwise, c);
}

Flow For::exec(ExecContext& c) const {
    // IEC 61131-3 §7.3.3.4.2: the bounds and the increment are evaluated once; the test comes
    // before each iteration. The counter runs in 64 bits, so a bound at the type's limit ends the
    // loop instead of wrapping around.
    std::int64_t v = from->eval(c).i;
    const std::int64_t end = to->eval(c).i;
    const std::int64_t step = by ? by->eval(c).i : 1;
    for (;;) {
        var->ref(c) = normalise(var->type.kind, Value{v, 0});
        if (step >= 0 ? v > end : v < end) return Flow::normal;
        c.tick(pos);
        const Flow f = run_block(body, c);
        if (f == Flow::exit) return Flow::normal;
        if (f == Flow::ret) return f;
        v = var->ref(c).i + step;
    }
}

Flow While::exec(ExecContext& c) const {
    while (cond->eval(c).i) {
        c.tick(pos);
        const Flow f = run_block(body, c);
        if (f == Flow::exit) return Flow::normal;
        if (f == Flow::ret) return f;
    }
    return Flow::normal;
}

Flow Repeat::exec(ExecContext& c) const {
    do {
        c.tick(pos);
        const Flow f = run_block(body, c);
        if (f == Flow::exit) return Flow::normal;
        if (f == Flow::ret) return f;
    } while (!until->eval(c).i);
    return Flow::normal;
}

Flow Exit::exec(ExecContext&) const { return Flow::exit; }
Flow Return::exec(ExecContext&) const { return Flow::ret; }

} // namespace rcsim::st
