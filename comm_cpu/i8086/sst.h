// rcsim — SingleStepTests 8086 runner (hardware-captured test vectors).
//
// Format: the v1 README of the SingleStepTests/8086 repository on GitHub: one JSON array
// per opcode (optionally gzip-compressed), each test with initial/final registers, RAM, the
// prefetched queue and the per-cycle bus trace; metadata.json gives each opcode's status and
// the mask of flags left undefined.
//
// Levels: 1 = final registers and RAM (undefined flags masked); 2 = total cycle count;
// 3 = the per-cycle trace (bus status, T-state, queue operation and byte on every cycle, the
// latched address on ALE cycles, the data on the active lanes where a transfer completes).
#pragma once

#include "comm_cpu/i8086/cpu.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace rcsim::i8086::sst {

/// Unreadable or malformed input; the message names the file and the reason.
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Per-opcode facts from metadata.json.
struct OpcodeInfo {
    std::string status = "unknown";
    std::uint16_t flags_mask = 0xFFFF;
    /// A file that holds every ModR/M reg value of an opcode whose metadata gives a status per
    /// reg value (8F, C6, C7: only /0 is defined): `status` is "by reg", each test has the
    /// status of its reg field.
    bool by_reg = false;
    std::array<std::string, 8> reg_status{};
    /// The status of a test whose ModR/M reg field is `reg` (-1: no ModR/M byte).
    const std::string& status_of(int reg) const { return by_reg && reg >= 0 ? reg_status[std::size_t(reg)] : status; }
    /// Whether any test of the file can have status `s`.
    bool has(const std::string& s) const {
        if (!by_reg) return status == s;
        for (const std::string& r : reg_status)
            if (r == s) return true;
        return false;
    }
};

class Metadata {
public:
    /// Loads metadata.json; throws InputError.
    static Metadata load(const std::string& path);
    /// The entry for a file stem such as "00" or "F6.7".
    OpcodeInfo lookup(const std::string& stem) const;
    /// The entry for a test file's path (its stem: the name without .json/.json.gz).
    OpcodeInfo lookup_file(const std::string& path) const;
    bool empty() const { return root_.is_null(); }

private:
    nlohmann::json root_;
};

struct FileResult {
    std::string path;
    std::string stem;
    std::string status;
    std::size_t tests = 0;
    std::size_t pass[4] = {0, 0, 0, 0}; // index 1..3 = levels
    std::string first_failure[4];       // a description of the first failure per level
    std::vector<std::string> diffs;     // side-by-side traces of failing tests (Runner::set_diff)
    std::uint64_t cycles = 0;           // emulated cycles over all tests
};

/// Reads a .json or .json.gz file whole (throws InputError naming the file).
std::string read_text(const std::string& path);
/// Expands files and directories into the sorted list of test files (excluding metadata.json).
std::vector<std::string> collect(const std::vector<std::string>& paths);

/// One test, validated and converted from JSON.
struct Test {
    std::string name;
    std::size_t idx = 0;
    Registers init;
    std::vector<std::pair<std::uint32_t, std::uint8_t>> ram_in, ram_out;
    std::vector<std::uint8_t> queue;
    std::size_t code_bytes = ~std::size_t(0); // length of "bytes": the harness then feeds NOPs
    int modrm_reg = -1; // the reg field of the byte after the prefixes and the opcode (-1: none)
    std::uint16_t fin[14] = {}; // final registers (8 general, 4 segment, ip, flags) ...
    bool fin_present[14] = {};  // ... and whether each was listed
    const nlohmann::json* cycles = nullptr;
};

/// The tests whose status (OpcodeInfo::status_of, by their ModR/M reg field) is `status`.
std::vector<Test> tests_of_status(std::vector<Test> tests, const OpcodeInfo& info, const std::string& status);

class Runner {
public:
    Runner();
    /// Validates and converts a parsed test array (throws InputError naming `file`).
    static std::vector<Test> convert(const nlohmann::json& tests, const std::string& file);
    /// Runs converted tests without comparison or trace (benchmarks); returns cycles executed.
    std::uint64_t run_converted(const std::vector<Test>& tests);
    /// What one test did on the bus: its clocks and its bus cycles in order (T1 clocks counted
    /// from the test's start).
    struct Timing {
        std::uint64_t cycles = 0;
        std::vector<BusRecord> bus;
    };
    /// Runs converted tests without comparison, with the per-cycle trace on (every clock
    /// simulated) or off (idle and waiting clocks taken in one step), and returns what each did.
    /// With `max_waits` > 0 the harness inserts 0..max_waits wait states per cycle, a fixed
    /// function of its address (no capture has them: for comparing the two ways alone).
    std::vector<Timing> timing_per_test(const std::vector<Test>& tests, bool trace, unsigned max_waits = 0);
    /// Runs every test of one file; throws InputError on unreadable or malformed content. With
    /// `only` set, a file whose status is by reg runs the tests of that status alone, and its
    /// stem names their reg values ("8F/0").
    FileResult run_file(const std::string& path, const Metadata& meta, const std::string& only = "");
    /// Keep a side-by-side trace (expected | emulated, first mismatch marked) of the first `n`
    /// tests per file that fail at `level` (2 or 3) in FileResult::diffs.
    void set_diff(std::size_t n, int level) {
        diff_n_ = n;
        diff_level_ = level;
    }

private:
    // The capture harness as the CPU saw it: RAM for data, and for code fetches the test's
    // instruction bytes in fetch order, then NOPs whatever the address (upstream README,
    // "Instruction Prefetching"). Matters when a jump lands on a byte of the instruction.
    struct Harness : BusHandler {
        std::uint8_t* ram = nullptr;
        std::size_t code_left = 0; // instruction bytes not yet fetched
        unsigned max_waits = 0;    // timing_per_test's wait states
        std::vector<BusRecord>* log = nullptr; // ... and its record of the cycles
        unsigned bus_access(Bus kind, std::uint32_t address, std::uint16_t& data, unsigned width,
                            cycles_t start) override;
        void answer(Bus kind, std::uint32_t address, std::uint16_t& data, unsigned width);
    };
    cycles_t run_one(const Test& t, const OpcodeInfo& info, FileResult* result, bool trace);
    bool check_state(const Test& t, const OpcodeInfo& info, std::string* why) const;
    bool check_trace(const nlohmann::json& cycles, std::string* why) const;
    std::string side_by_side(const Test& t, cycles_t used) const;

    Harness harness_;
    std::unique_ptr<std::uint8_t[]> ram_;
    std::vector<std::uint32_t> touched_;
    Cpu cpu_;
    std::vector<CycleRecord> trace_;
    std::size_t diff_n_ = 0;
    int diff_level_ = 3;
};

} // namespace rcsim::i8086::sst
