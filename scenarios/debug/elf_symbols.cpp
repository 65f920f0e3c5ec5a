// rcsim — the symbol-only ELF file (elf_symbols.h). Field layouts: the System V ABI, "Object
// Files" (ELF32 header, section header, symbol table entry).
#include "scenarios/debug/elf_symbols.h"

#include "scenarios/debug/dwarf_types.h"

#include <fstream>

namespace rcsim::debug {

namespace {

// ELF constants used here (System V ABI).
constexpr std::uint16_t ET_EXEC = 2, EM_NONE = 0; // EM_NONE: elf_symbols.h says why
constexpr std::uint32_t SHT_PROGBITS = 1, SHT_SYMTAB = 2, SHT_STRTAB = 3, SHT_NOBITS = 8;
constexpr std::uint32_t SHF_WRITE = 1, SHF_ALLOC = 2, SHF_EXECINSTR = 4;
constexpr std::uint8_t STB_LOCAL = 0, STB_GLOBAL = 1, STT_OBJECT = 1, STT_FUNC = 2;
constexpr unsigned kEhdr = 52, kShdr = 40, kSym = 16;

enum Section : std::uint16_t { s_null, s_text, s_data, s_symtab, s_strtab, s_shstrtab, s_abbrev, s_info, s_count };

class Out {
public:
    void u8(std::uint8_t v) { b_.push_back(v); }
    void u16(std::uint16_t v) { u8(std::uint8_t(v)); u8(std::uint8_t(v >> 8)); }
    void u32(std::uint32_t v) { u16(std::uint16_t(v)); u16(std::uint16_t(v >> 16)); }
    void bytes(const std::string& s) { b_.insert(b_.end(), s.begin(), s.end()); }
    std::size_t size() const { return b_.size(); }
    std::vector<std::uint8_t> take() { return std::move(b_); }

private:
    std::vector<std::uint8_t> b_;
};

/// A string table: "\0name\0name\0..."; add() returns the name's offset.
struct StringTable {
    std::string text = std::string(1, '\0');
    std::uint32_t add(const std::string& s) {
        const auto at = std::uint32_t(text.size());
        text += s;
        text += '\0';
        return at;
    }
};

struct SectionHeader {
    std::uint32_t name = 0, type = 0, flags = 0, addr = 0, offset = 0, size = 0, link = 0, info = 0,
                  align = 1, entsize = 0;
};

} // namespace

std::vector<std::uint8_t> elf_image(const SymbolTable& table, const std::map<std::string, CType>& declarations) {
    StringTable shstr, str;
    SectionHeader sh[s_count];
    sh[s_text] = {shstr.add(".text"), SHT_NOBITS, SHF_ALLOC | SHF_EXECINSTR, SymbolTable::rom_base, 0,
                  SymbolTable::rom_end - SymbolTable::rom_base, 0, 0, 1, 0};
    sh[s_data] = {shstr.add(".data"), SHT_NOBITS, SHF_ALLOC | SHF_WRITE, 0, 0, SymbolTable::rom_base, 0, 0, 1, 0};
    sh[s_symtab].name = shstr.add(".symtab");
    sh[s_strtab].name = shstr.add(".strtab");
    sh[s_shstrtab].name = shstr.add(".shstrtab");
    sh[s_abbrev].name = shstr.add(".debug_abbrev");
    sh[s_info].name = shstr.add(".debug_info");
    const DwarfSections dwarf = dwarf_variables(table, declarations);

    // The symbol table: the null entry, the local symbols (C statics), then the globals: the ABI
    // wants every STB_LOCAL entry before the first global, whose index is the table's sh_info.
    Out syms;
    for (unsigned i = 0; i < kSym; ++i) syms.u8(0);
    std::uint32_t first_global = 1;
    for (const bool local : {true, false}) {
        for (const Symbol& s : table.symbols()) {
            if (s.local != local) continue;
            const bool code = s.kind == Symbol::Kind::code;
            syms.u32(str.add(s.name));
            syms.u32(s.address);
            syms.u32(s.size);
            syms.u8(std::uint8_t((local ? STB_LOCAL : STB_GLOBAL) << 4 | (code ? STT_FUNC : STT_OBJECT)));
            syms.u8(0);
            // A symbol outside its kind's usual range still lands in the section that spans it.
            syms.u16(s.address >= SymbolTable::rom_base && s.address < SymbolTable::rom_end ? s_text : s_data);
            if (local) ++first_global;
        }
    }
    const auto symtab = syms.take();

    // File layout: header, .symtab, .strtab, .shstrtab, .debug_abbrev, .debug_info, section
    // headers (4-byte aligned).
    std::uint32_t at = kEhdr;
    sh[s_symtab] = {sh[s_symtab].name, SHT_SYMTAB, 0, 0, at, std::uint32_t(symtab.size()), s_strtab, first_global, 4, kSym};
    at += sh[s_symtab].size;
    sh[s_strtab] = {sh[s_strtab].name, SHT_STRTAB, 0, 0, at, std::uint32_t(str.text.size()), 0, 0, 1, 0};
    at += sh[s_strtab].size;
    sh[s_shstrtab] = {sh[s_shstrtab].name, SHT_STRTAB, 0, 0, at, std::uint32_t(shstr.text.size()), 0, 0, 1, 0};
    at += sh[s_shstrtab].size;
    sh[s_abbrev] = {sh[s_abbrev].name, SHT_PROGBITS, 0, 0, at, std::uint32_t(dwarf.abbrev.size()), 0, 0, 1, 0};
    at += sh[s_abbrev].size;
    sh[s_info] = {sh[s_info].name, SHT_PROGBITS, 0, 0, at, std::uint32_t(dwarf.info.size()), 0, 0, 1, 0};
    at += sh[s_info].size;
    const std::uint32_t shoff = (at + 3) & ~3u;

    Out f;
    f.bytes("\x7f" "ELF");
    f.u8(1); // ELFCLASS32
    f.u8(1); // ELFDATA2LSB
    f.u8(1); // EV_CURRENT
    for (int i = 0; i < 9; ++i) f.u8(0); // ELFOSABI_NONE, padding
    f.u16(ET_EXEC);
    f.u16(EM_NONE);
    f.u32(1);       // e_version
    f.u32(0xFFFF0); // e_entry: the reset vector FFFF:0000
    f.u32(0);       // e_phoff: no program headers
    f.u32(shoff);
    f.u32(0);       // e_flags
    f.u16(kEhdr);
    f.u16(32);      // e_phentsize (ELF32 program header size; none present)
    f.u16(0);       // e_phnum
    f.u16(kShdr);
    f.u16(s_count);
    f.u16(s_shstrtab);
    for (auto b : symtab) f.u8(b);
    f.bytes(str.text);
    f.bytes(shstr.text);
    for (auto b : dwarf.abbrev) f.u8(b);
    for (auto b : dwarf.info) f.u8(b);
    while (f.size() < shoff) f.u8(0);
    for (const SectionHeader& h : sh) {
        for (std::uint32_t v : {h.name, h.type, h.flags, h.addr, h.offset, h.size, h.link, h.info, h.align, h.entsize})
            f.u32(v);
    }
    return f.take();
}

void write_elf(const SymbolTable& table, const std::string& path, const std::map<std::string, CType>& declarations) {
    const auto image = elf_image(table, declarations);
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(image.data()), std::streamsize(image.size()));
    out.close();
    if (!out) throw SymbolError(path + ": cannot write the symbol file");
}

} // namespace rcsim::debug
