#include "scenarios/run/cause_symbols.h"

#include <cstdio>
#include <memory>

namespace rcsim {

SymbolOf cause_symbols(debug::SymbolTable symbols) {
    if (symbols.empty()) return {};
    // Shared: a SymbolOf is copied into every cause's making.
    auto table = std::make_shared<const debug::SymbolTable>(std::move(symbols));
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
