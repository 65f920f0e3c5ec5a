// rcsim — the DWARF of symbols.elf (dwarf_types.h).
#include "scenarios/debug/dwarf_types.h"

namespace rcsim::debug {

namespace {

// DWARF 4 constants used here (section 7).
enum : std::uint8_t {
    DW_TAG_array_type = 0x01, DW_TAG_compile_unit = 0x11, DW_TAG_subrange_type = 0x21, DW_TAG_base_type = 0x24,
    DW_TAG_variable = 0x34,
};
enum : std::uint8_t {
    DW_AT_location = 0x02, DW_AT_name = 0x03, DW_AT_byte_size = 0x0b, DW_AT_language = 0x13, DW_AT_producer = 0x25,
    DW_AT_upper_bound = 0x2f, DW_AT_encoding = 0x3e, DW_AT_external = 0x3f, DW_AT_type = 0x49,
};
enum : std::uint8_t {
    DW_FORM_string = 0x08, DW_FORM_data1 = 0x0b, DW_FORM_udata = 0x0f, DW_FORM_ref4 = 0x13, DW_FORM_exprloc = 0x18,
    DW_FORM_flag_present = 0x19,
};
enum : std::uint8_t { DW_ATE_signed = 0x05, DW_ATE_signed_char = 0x06, DW_ATE_unsigned = 0x07, DW_ATE_unsigned_char = 0x08 };
constexpr std::uint8_t DW_LANG_C89 = 0x01, DW_OP_addr = 0x03, DW_CHILDREN_no = 0, DW_CHILDREN_yes = 1;
constexpr std::uint32_t kUnitHeader = 11; // unit_length 4, version 2, debug_abbrev_offset 4, address_size 1

// Abbreviation codes.
enum : std::uint8_t { a_unit = 1, a_base, a_array, a_subrange, a_global, a_static };

struct Bytes {
    std::vector<std::uint8_t> b;
    void u8(std::uint8_t v) { b.push_back(v); }
    void u16(std::uint16_t v) { u8(std::uint8_t(v)); u8(std::uint8_t(v >> 8)); }
    void u32(std::uint32_t v) { u16(std::uint16_t(v)); u16(std::uint16_t(v >> 16)); }
    void uleb(std::uint64_t v) {
        do {
            std::uint8_t byte = v & 0x7F;
            v >>= 7;
            u8(v ? byte | 0x80 : byte);
        } while (v);
    }
    void str(const std::string& s) {
        b.insert(b.end(), s.begin(), s.end());
        u8(0);
    }
};

std::vector<std::uint8_t> abbreviations() {
    Bytes a;
    const auto entry = [&a](std::uint8_t code, std::uint8_t tag, std::uint8_t children,
                            std::initializer_list<std::pair<std::uint8_t, std::uint8_t>> attrs) {
        a.uleb(code);
        a.uleb(tag);
        a.u8(children);
        for (const auto& [at, form] : attrs) {
            a.uleb(at);
            a.uleb(form);
        }
        a.u8(0);
        a.u8(0);
    };
    entry(a_unit, DW_TAG_compile_unit, DW_CHILDREN_yes,
          {{DW_AT_name, DW_FORM_string}, {DW_AT_language, DW_FORM_data1}, {DW_AT_producer, DW_FORM_string}});
    entry(a_base, DW_TAG_base_type, DW_CHILDREN_no,
          {{DW_AT_name, DW_FORM_string}, {DW_AT_encoding, DW_FORM_data1}, {DW_AT_byte_size, DW_FORM_data1}});
    entry(a_array, DW_TAG_array_type, DW_CHILDREN_yes, {{DW_AT_type, DW_FORM_ref4}});
    entry(a_subrange, DW_TAG_subrange_type, DW_CHILDREN_no, {{DW_AT_upper_bound, DW_FORM_udata}});
    entry(a_global, DW_TAG_variable, DW_CHILDREN_no,
          {{DW_AT_name, DW_FORM_string}, {DW_AT_type, DW_FORM_ref4}, {DW_AT_external, DW_FORM_flag_present},
           {DW_AT_location, DW_FORM_exprloc}});
    entry(a_static, DW_TAG_variable, DW_CHILDREN_no,
          {{DW_AT_name, DW_FORM_string}, {DW_AT_type, DW_FORM_ref4}, {DW_AT_location, DW_FORM_exprloc}});
    a.u8(0);
    return a.b;
}

/// The DIEs of the unit's children, each type once; offsets are from the unit's start.
class Dies {
public:
    explicit Dies(std::uint32_t first) : first_(first) {}

    std::uint32_t type(const CType& t) {
        const std::string element = t.pointer ? "near_ptr" : t.base;
        std::uint32_t ref = base(element, t.pointer ? 2 : t.base_size, t.pointer ? false : t.is_signed);
        if (t.dims.empty()) return ref;
        std::string key = element;
        for (auto d : t.dims) key += "[" + std::to_string(d) + "]";
        if (auto it = types_.find(key); it != types_.end()) return it->second;
        const std::uint32_t at = offset();
        out_.uleb(a_array);
        out_.u32(ref);
        for (auto d : t.dims) {
            out_.uleb(a_subrange);
            out_.uleb(d - 1);
        }
        out_.u8(0); // the array's children end
        return types_[key] = at;
    }

    void variable(const Symbol& s, std::uint32_t type_ref) {
        out_.uleb(s.local ? a_static : a_global);
        out_.str(s.name);
        out_.u32(type_ref);
        out_.uleb(5); // the location: DW_OP_addr and its 4-byte address
        out_.u8(DW_OP_addr);
        out_.u32(s.address);
    }

    std::vector<std::uint8_t>& bytes() { return out_.b; }

private:
    std::uint32_t offset() const { return first_ + std::uint32_t(out_.b.size()); }

    std::uint32_t base(const std::string& name, unsigned size, bool is_signed) {
        if (auto it = types_.find(name); it != types_.end()) return it->second;
        const std::uint32_t at = offset();
        out_.uleb(a_base);
        out_.str(name);
        const bool chr = size == 1 && name.find("char") != std::string::npos;
        out_.u8(chr ? (is_signed ? DW_ATE_signed_char : DW_ATE_unsigned_char) : (is_signed ? DW_ATE_signed : DW_ATE_unsigned));
        out_.u8(std::uint8_t(size));
        return types_[name] = at;
    }

    std::uint32_t first_;
    Bytes out_;
    std::map<std::string, std::uint32_t> types_;
};

} // namespace

CType variable_type(const Symbol& s, const std::map<std::string, CType>& declarations) {
    if (const auto d = declarations.find(s.name); d != declarations.end() && (s.size == 0 || d->second.size() <= s.size))
        return d->second;
    CType t;
    if (s.size == 0) {
        t.base.clear();
    } else if (s.size == 2) {
        t.base = "unsigned int";
    } else {
        t.base = "unsigned char";
        t.base_size = 1;
        if (s.size > 1) t.dims.push_back(s.size);
    }
    return t;
}

DwarfSections dwarf_variables(const SymbolTable& table, const std::map<std::string, CType>& declarations) {
    Bytes unit;
    unit.uleb(a_unit);
    unit.str("rom");
    unit.u8(DW_LANG_C89);
    unit.str("rcsim (from the ROM's map and C declarations)");
    Dies dies(kUnitHeader + std::uint32_t(unit.b.size()));
    for (const Symbol& s : table.symbols()) {
        if (s.kind != Symbol::Kind::data) continue;
        const CType t = variable_type(s, declarations);
        if (t.base.empty()) continue;
        dies.variable(s, dies.type(t));
    }
    auto& children = dies.bytes();
    unit.b.insert(unit.b.end(), children.begin(), children.end());
    unit.u8(0); // the unit's children end

    Bytes info;
    info.u32(std::uint32_t(kUnitHeader - 4 + unit.b.size())); // unit_length: what follows it
    info.u16(4);                                               // version
    info.u32(0);                                               // debug_abbrev_offset
    info.u8(4);                                                // address_size
    info.b.insert(info.b.end(), unit.b.begin(), unit.b.end());
    return {abbreviations(), info.b};
}

} // namespace rcsim::debug
