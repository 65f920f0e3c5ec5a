#include "scenarios/coverage/counters.h"

#include <map>
#include <utility>

namespace rcsim::coverage {

namespace {

bool is_prefix(std::uint8_t b) {
    return b == 0x26 || b == 0x2E || b == 0x36 || b == 0x3E || b == 0xF0 || b == 0xF2 || b == 0xF3;
}

/// 70-7F (and 60-6F, which the 8086 decodes as the same Jcc), E0-E3.
bool is_conditional_jump(std::uint8_t op) { return (op >= 0x60 && op <= 0x7F) || (op >= 0xE0 && op <= 0xE3); }

} // namespace

Counters::Counters(std::uint32_t base, std::vector<std::uint8_t> code)
    : base_(base), jump_(code.size()), executed_(code.size()), taken_(code.size()), not_taken_(code.size()) {
    for (std::size_t i = 0; i < code.size(); ++i) {
        std::size_t k = i;
        while (k < code.size() && k < i + 4 && is_prefix(code[k])) ++k; // prefixes are part of the instruction
        if (k < code.size() && is_conditional_jump(code[k])) jump_[i] = code[k];
    }
}

bool Counters::taken(std::uint8_t op, const i8086::Registers& r) {
    using namespace i8086::flag;
    const bool cf = r.flags & CF, zf = r.flags & ZF, sf = r.flags & SF, of = r.flags & OF, pf = r.flags & PF;
    const std::uint16_t cx = r.r[i8086::CX];
    if (op >= 0xE0) {
        const bool more = cx != 1; // LOOPs decrement CX first, then test it for 0
        switch (op) {
        case 0xE0: return more && !zf; // LOOPNZ
        case 0xE1: return more && zf;  // LOOPZ
        case 0xE2: return more;        // LOOP
        default: return cx == 0;       // JCXZ
        }
    }
    bool c = false;
    switch ((op >> 1) & 7) { // the condition of the even code; the odd one is its negation
    case 0: c = of; break;                     // JO
    case 1: c = cf; break;                     // JB
    case 2: c = zf; break;                     // JE
    case 3: c = cf || zf; break;               // JBE
    case 4: c = sf; break;                     // JS
    case 5: c = pf; break;                     // JP
    case 6: c = sf != of; break;               // JL
    default: c = zf || sf != of; break;        // JLE
    }
    return (op & 1) ? !c : c;
}

Tracefile Counters::tracefile(const CodeMap& map) const {
    Tracefile t;
    for (const std::string& f : map.files) t.files[f]; // a file nothing ran in is still listed
    std::map<std::pair<std::size_t, unsigned>, unsigned> blocks; // (file, line) -> branch sites seen
    for (const CodeSite& s : map.sites) {
        FileCoverage& f = t.files[map.files[s.file]];
        std::uint64_t& line = f.lines[s.line];
        for (std::uint32_t a = s.linear; a < s.end; ++a) {
            const std::uint64_t ran = executed(a);
            if (s.leads_line || map.ranges) line += ran;
            if (!jump_opcode(a) || (map.ranges && ran == 0)) continue; // a range's bytes are not all instructions
            const unsigned block = blocks[{s.file, s.line}]++;
            auto& taken_way = f.branches[{s.line, block, 0}];
            auto& other_way = f.branches[{s.line, block, 1}];
            if (ran) taken_way = taken(a), other_way = not_taken(a);
        }
    }
    for (const CodeFunction& fn : map.functions) {
        auto& rec = t.files[map.files[fn.file]].functions[fn.name];
        rec.line = fn.line;
        rec.count += executed(fn.linear);
    }
    return t;
}

} // namespace rcsim::coverage
