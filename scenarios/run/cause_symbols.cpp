#include "scenarios/run/cause_symbols.h"

#include "scenarios/trace/profile_run.h"
#include "models/plumbing/config_error.h"

#include <cstdio>
#include <memory>

namespace rcsim {

SymbolOf cause_symbols(const std::string& file, const std::string& rom) {
    std::shared_ptr<const debug::SymbolTable> table;
    try {
        table = std::make_shared<const debug::SymbolTable>(trace::run_symbols(file, rom));
    } catch (const ConfigError&) {
        return {};
    }
    if (table->empty()) return {};
    return [table](std::uint32_t linear) -> std::string {
        const debug::Symbol* s = table->containing(linear);
        if (!s || s->kind != debug::Symbol::Kind::code) return "";
        if (s->address == linear) return s->name;
        char buf[24];
        std::snprintf(buf, sizeof buf, "+0x%X", static_cast<unsigned>(linear - s->address));
        return s->name + buf;
    };
}

} // namespace rcsim
