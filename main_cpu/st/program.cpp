// rcsim — the Structured Text program runtime. See program.h.
#include "main_cpu/st/program.h"

#include "main_cpu/motion/plcopen.h"

#include <cmath>
#include <cstdio>

namespace rcsim::st {

StProgram::StProgram(const std::string& text, const std::string& file, std::vector<motion::McAxis*> axes,
                     std::vector<motion::MC_Power*> power)
    : StProgram(text, file, std::move(axes), std::move(power), Config{}) {}

StProgram::StProgram(const std::string& text, const std::string& file, std::vector<motion::McAxis*> axes,
                     std::vector<motion::MC_Power*> power, Config cfg)
    : unit_(compile(text, file, static_cast<unsigned>(axes.size()))) {
    if (unit_->programs.empty()) throw CompileError(file + ":1:1: the text has no PROGRAM");
    ctx_.axes = std::move(axes);
    ctx_.power = std::move(power);
    ctx_.budget = cfg.budget;
}

StProgram::~StProgram() = default;

bool StProgram::has_program(const std::string& name) const { return unit_->programs.count(upper(name)) != 0; }

std::string StProgram::start(const std::string& name) {
    const auto it = unit_->programs.find(upper(name));
    if (it == unit_->programs.end()) return "no PROGRAM named '" + name + "'";
    if (running_) return "program '" + current_ + "' is running";
    // A cold start: the globals and the program from their initial values.
    globals_ = unit_->globals.instantiate();
    program_ = it->second->instantiate();
    current_ = it->second->name;
    error_.clear();
    cycles_ = max_statements_ = 0;
    running_ = true;
    return "";
}

void StProgram::stop() {
    if (!running_) return;
    running_ = false;
    // The program no longer supervises the axes: the moving ones decelerate to a stop.
    for (motion::McAxis* a : ctx_.axes)
        if (a && a->api().InMotion(static_cast<int>(a->index()))) a->api().SlowStop(static_cast<int>(a->index()), 0);
}

void StProgram::fail(const std::string& message) {
    running_ = false;
    error_ = message;
    for (motion::McAxis* a : ctx_.axes)
        if (a && a->state() != motion::AxisState::error_stop) a->enter_error(program_error);
}

ProgramWork StProgram::cycle(const sc_core::sc_time& now) { return run_once(std::llround(now.to_seconds() * 1e6)); }

ProgramWork StProgram::run_once(std::int64_t now_us) {
    if (!running_) return {};
    ctx_.now_us = now_us;
    ctx_.executed = 0;
    ctx_.motion_calls = 0;
    ctx_.globals = globals_.get();
    ctx_.self = nullptr;
    try {
        run_pou(*program_, ctx_);
    } catch (const RuntimeError& e) {
        fail(e.what());
    } catch (const std::exception& e) {
        fail(current_ + ": internal error: " + e.what());
    }
    ++cycles_;
    max_statements_ = std::max(max_statements_, ctx_.executed);
    return ProgramWork{ctx_.executed, ctx_.motion_calls};
}

namespace {

nlohmann::json to_json(const Type& t, const Value& v) {
    switch (t.kind) {
    case Kind::Bool: return v.i != 0;
    case Kind::Real: case Kind::Lreal: return v.r;
    case Kind::Time: {
        char b[40];
        std::snprintf(b, sizeof b, "T#%gms", static_cast<double>(v.i) / 1000.0);
        return b;
    }
    case Kind::AxisRef: return v.i < 0 ? nlohmann::json("none") : nlohmann::json("Axis" + std::to_string(v.i));
    default: return v.i;
    }
}

/// A datum of any type: arrays as lists, STRUCTs as objects, STRINGs as text, enumeration values
/// by name.
nlohmann::json datum_json(const Type& t, const Value* p) {
    switch (t.kind) {
    case Kind::Array: {
        nlohmann::json a = nlohmann::json::array();
        const Type e = t.element();
        for (std::int64_t k = 0; k <= t.hi - t.lo; ++k) a.push_back(datum_json(e, p + k * static_cast<std::int64_t>(e.slots())));
        return a;
    }
    case Kind::Struct: {
        nlohmann::json o = nlohmann::json::object();
        for (const StructType::Member& m : t.st->members) o[m.name] = datum_json(m.type, p + m.offset);
        return o;
    }
    case Kind::String: return unpack(p);
    case Kind::Enum: {
        const std::string n = t.en->value_name(p->i);
        return n.empty() ? nlohmann::json(p->i) : nlohmann::json(n);
    }
    default: return to_json(t, *p);
    }
}

void add_vars(const Instance& inst, const std::string& prefix, bool interface_only, nlohmann::json& out) {
    for (const VarInfo& v : inst.type->vars) {
        if (v.read_only) continue;
        if (interface_only && v.kind != VarKind::input && v.kind != VarKind::output) continue;
        const std::string name = prefix + v.name;
        if (v.type.kind == Kind::Fb) {
            add_vars(*inst.fbs[v.slot], name + ".", true, out);
        } else if (v.type.fb_array()) {
            for (std::int64_t k = v.type.lo; k <= v.type.hi; ++k)
                add_vars(*inst.fbs[v.slot + static_cast<std::size_t>(k - v.type.lo)],
                         name + "[" + std::to_string(k) + "].", true, out);
        } else if (v.kind != VarKind::in_out) {
            out[name] = datum_json(v.type, &inst.vars[v.slot]);
        }
    }
}

} // namespace

Value StProgram::value(const std::string& path) const { return *const_cast<StProgram*>(this)->locate(path); }

void StProgram::set_value(const std::string& path, Value v) { *locate(path) = v; }

Value* StProgram::locate(const std::string& path) {
    if (!program_) throw std::out_of_range("no program has been started");
    std::string head = path, member;
    std::int64_t index = 0;
    bool indexed = false;
    if (const auto dot = path.find('.'); dot != std::string::npos) {
        head = path.substr(0, dot);
        member = path.substr(dot + 1);
    }
    if (const auto br = head.find('['); br != std::string::npos) {
        try {
            index = std::stoll(head.substr(br + 1));
        } catch (const std::logic_error&) {
            throw std::out_of_range("no element " + path);
        }
        head = head.substr(0, br);
        indexed = true;
    }
    Instance* inst = program_.get();
    const VarInfo* v = inst->type->find(upper(head));
    if (!v) {
        inst = globals_.get();
        v = inst->type->find(upper(head));
    }
    if (!v) throw std::out_of_range("no variable '" + head + "'");
    // Only single-slot data: a forced STRING length or STRUCT slot could break what the compiler
    // laid out.
    if (indexed && !member.empty()) { // t[2].Q: an output of one of an ARRAY OF a block
        if (!v->type.fb_array() || index < v->type.lo || index > v->type.hi)
            throw std::out_of_range("no element " + path);
        Instance& fb = *inst->fbs[v->slot + static_cast<std::size_t>(index - v->type.lo)];
        const VarInfo* m = fb.type->find(upper(member));
        if (!m || m->kind == VarKind::in_out || !m->type.elementary())
            throw std::out_of_range("no elementary member '" + member + "' in " + head);
        return &fb.vars[m->slot];
    }
    if (!member.empty()) {
        if (v->type.kind == Kind::Struct) {
            const StructType::Member* m = v->type.st->find(upper(member));
            if (!m || !m->type.elementary()) throw std::out_of_range("no elementary member '" + member + "' in " + head);
            return &inst->vars[v->slot + m->offset];
        }
        if (v->type.kind != Kind::Fb) throw std::out_of_range("'" + head + "' has no members");
        Instance& fb = *inst->fbs[v->slot];
        const VarInfo* m = fb.type->find(upper(member));
        if (!m || m->kind == VarKind::in_out || !m->type.elementary())
            throw std::out_of_range("no elementary member '" + member + "' in " + head);
        return &fb.vars[m->slot];
    }
    if (indexed) {
        if (v->type.kind != Kind::Array || index < v->type.lo || index > v->type.hi || !v->type.element().elementary())
            throw std::out_of_range("no element " + path);
        return &inst->vars[v->slot + static_cast<std::size_t>(index - v->type.lo) * v->type.element().slots()];
    }
    if (!v->type.elementary()) throw std::out_of_range("'" + head + "' is not elementary");
    return &inst->vars[v->slot];
}

nlohmann::json StProgram::variables() const {
    nlohmann::json out = nlohmann::json::object();
    if (program_) add_vars(*program_, "", false, out);
    if (globals_) add_vars(*globals_, "", false, out);
    return out;
}

nlohmann::json StProgram::report() const {
    return {{"program", current_},
            {"state", running_ ? "RUNNING" : error_.empty() ? "STOPPED" : "ERROR"},
            {"error", error_},
            {"cycles", cycles_},
            {"max_statements_per_cycle", max_statements_},
            {"statement_budget", ctx_.budget},
            {"variables", variables()}};
}

} // namespace rcsim::st
