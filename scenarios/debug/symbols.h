// rcsim — the symbol table of a communication-board ROM, for the debugger and the profiler.
//
// Addresses are linear (20-bit physical, CS*16+IP), the form the bus cycles and the gdb stub use.
// Four sources (docs/tools.md "Symbols"):
//   - the `ld86 -M` map of the built firmware (build/comm_fw.map): symbols of segment 0 (code,
//     linked at offset 0 of the ROM) and segment 3 (data/bss, at DS:offset): the globals, and the
//     C `static` functions and variables (local, see load_ld86_map);
//   - nasm's map file (`[map all FILE]` in the source) of a ROM assembled with `-f bin`;
//   - the "Publics by Value" / "Publics by Name" map of MS LINK, Borland TLINK and the locators
//     (Paradigm LOCATE): SSSS:OOOO rows, relative to a load segment for an .EXE's map;
//   - a simple text format, one symbol a line: `NAME ADDRESS [SIZE [code|data]]`.
// A symbol without a size extends to the next symbol of its kind (code or data) or to the end of
// its region, so that containing() finds the function an instruction belongs to.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace rcsim::debug {

struct Symbol {
    enum class Kind { code, data };
    std::string name;          // without bcc's leading underscore (`rs232_isr`, not `_rs232_isr`)
    std::uint32_t address = 0; // linear
    std::uint32_t size = 0;    // bytes; 0 = a label that contains no address
    Kind kind = Kind::code;
    bool local = false;        // file scope (a C `static`): ld86's flag r, STB_LOCAL in the ELF
    /// The name as the map spells it when `name` differs (`_main` for `main`); find() takes it too.
    std::string map_name;
};

/// An absolute value of a map (nasm's `equ`, a Publics map's `Abs` row): not code or data, so
/// not a Symbol (it contains no address), kept by name.
struct Constant {
    std::string name;
    std::uint64_t value = 0; // nasm writes -1 as FFFFFFFFFFFFFFFF
};

/// A malformed symbol file; what() is "FILE:LINE: reason" (or "FILE: reason").
class SymbolError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Where an ld86 map's segments sit in the 8086's address space.
struct Ld86Layout {
    std::uint32_t code_base = 0xF0000; // segment 0 at ROM offset 0 (CS = F000)
    /// Segment 3 (data and bss) at data_base + offset. < 0: DATA_SEG*16 from the map's absolute
    /// symbol DATA_SEG (the firmware's crt0.s defines it); a map without one loads code only.
    std::int64_t data_base = -1;
};

class SymbolTable {
public:
    /// The ROM of the communication board: 64 KB at F0000-FFFFF (docs/system.md §3.1).
    static constexpr std::uint32_t rom_base = 0xF0000;
    static constexpr std::uint32_t rom_end = 0x100000;

    /// Reads `spec` = FILE or FILE@SEG in whichever of the four formats FILE is in (detected from
    /// its content). SEG (1-4 hex digits) is the load segment of a map's image: where a Publics
    /// map's segment 0000, a nasm image's first byte, an ld86 map's code segment sit (SEG:0000).
    static SymbolTable load(const std::string& spec);
    /// Globals (flag R) and C statics: the locals (flag r) with bcc's leading underscore, which
    /// bcc gives every C identifier. The other locals are as86 labels of hand-written assembly,
    /// mostly branch targets inside a routine: they stay out, so a routine is one symbol. A
    /// static whose name another symbol has too is named MODULE__NAME (`main__send`: gdb reads a
    /// colon as FILE:FUNCTION).
    static SymbolTable load_ld86_map(const std::string& path, const Ld86Layout& layout = {});
    /// `base` is where the image's first byte sits (the ROM: F0000).
    static SymbolTable load_nasm_map(const std::string& path, std::uint32_t base = rom_base);
    static SymbolTable load_text(const std::string& path);
    /// A linker's or locator's map with a `Address  Publics by Value` (or `by Name`) section:
    /// SSSS:OOOO at linear (load_segment + SSSS)*16 + OOOO. Code or data from the class of the
    /// segment listed at the map's head (CODE: code), else code in the ROM and data elsewhere.
    static SymbolTable load_publics_map(const std::string& path, std::uint16_t load_segment = 0);

    /// Adds a symbol (throws SymbolError on a duplicate name); sizes of 0 stay 0 until
    /// fill_sizes() runs.
    void add(Symbol symbol, const std::string& where = "");
    /// Gives every symbol of size 0 the distance to the next symbol of its kind, or for the last
    /// one the distance to `code_end` / `data_end` (0 leaves it a label).
    void fill_sizes(std::uint32_t code_end, std::uint32_t data_end);

    /// By name, or by the map's spelling of it (`_main`) when no symbol has that name.
    const Symbol* find(std::string_view name) const;
    /// The symbol whose [address, address + size) holds `linear` (the function an instruction
    /// belongs to, the variable a byte belongs to); nullptr when none does.
    const Symbol* containing(std::uint32_t linear) const;
    /// All symbols, sorted by address (then name).
    const std::vector<Symbol>& symbols() const { return symbols_; }
    /// Adds an absolute value (throws SymbolError on a duplicate name).
    void add_constant(Constant constant, const std::string& where = "");
    const Constant* constant(std::string_view name) const;
    /// The absolute values, in the map's order.
    const std::vector<Constant>& constants() const { return constants_; }

    bool empty() const { return symbols_.empty(); }
    std::size_t size() const { return symbols_.size(); }

private:
    /// add() without the sort: fill_sizes(), which every loader ends with, sorts.
    void append(Symbol symbol, const std::string& where);
    void sort();

    std::vector<Symbol> symbols_;
    std::unordered_map<std::string, std::size_t> by_name_; // index into symbols_
    std::unordered_map<std::string, std::size_t> by_map_name_; // index into symbols_
    std::vector<Constant> constants_;
    std::uint32_t max_size_ = 0; // the longest symbol, bounds the search of containing()
};

} // namespace rcsim::debug
