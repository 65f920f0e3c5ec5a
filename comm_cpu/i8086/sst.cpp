// rcsim — SingleStepTests 8086 runner. See sst.h.
#include "comm_cpu/i8086/sst.h"

#include "models/plumbing/hex.h"

#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace rcsim::i8086::sst {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr std::uint32_t kRamSize = 1u << 20;
// Input caps (docs/scenarios.md "Limits"): the largest SingleStepTests 8086 file is a few MB, its
// text a few tens of MB; these bound what a wrong path can make rcsim read and parse.
constexpr std::uintmax_t kMaxFileBytes = 64u << 20;
constexpr std::size_t kMaxTextBytes = 256u << 20;
constexpr std::uint8_t kFill = 0x90; // bytes the suite did not list are NOPs (upstream README)

const char* const kRegNames[] = {"ax", "cx", "dx", "bx", "sp", "bp", "si", "di"};
const char* const kSegNames[] = {"es", "cs", "ss", "ds"};

[[noreturn]] void fail(const std::string& file, const std::string& why) {
    throw InputError(file + ": " + why);
}

std::string stem_of(const std::string& path) {
    std::string name = fs::path(path).filename().string();
    for (const char* ext : {".json.gz", ".json", ".gz"}) {
        const std::size_t n = std::strlen(ext);
        if (name.size() > n && name.compare(name.size() - n, n, ext) == 0) {
            name.resize(name.size() - n);
            break;
        }
    }
    return name;
}

std::uint32_t get_u32(const json& j, const std::string& file, const std::string& what, std::uint32_t max) {
    if (!j.is_number_unsigned() && !(j.is_number_integer() && j.get<std::int64_t>() >= 0))
        fail(file, what + " is not a non-negative integer: " + j.dump());
    const std::uint64_t v = j.get<std::uint64_t>();
    if (v > max) fail(file, what + " out of range: " + std::to_string(v));
    return static_cast<std::uint32_t>(v);
}

} // namespace

// ---------------------------------------------------------------------------------------------

std::string read_text(const std::string& path) {
    // A device (/dev/zero) or a huge file would be read whole before anything could fail.
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (fs::exists(st) && !fs::is_regular_file(st)) fail(path, "not a regular file");
    const std::uintmax_t size = fs::file_size(path, ec);
    if (!ec && size > kMaxFileBytes)
        fail(path, std::to_string(size) + " bytes; a test file is at most " + std::to_string(kMaxFileBytes));
    gzFile f = gzopen(path.c_str(), "rb"); // reads plain files transparently
    if (!f) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
    std::string out;
    char buf[1 << 16];
    for (;;) {
        const int n = gzread(f, buf, sizeof buf);
        if (n < 0) {
            int err = 0;
            const std::string msg = gzerror(f, &err);
            gzclose(f);
            throw InputError(path + ": read error (" + msg + ")");
        }
        if (n == 0) break;
        if (out.size() + static_cast<std::size_t>(n) > kMaxTextBytes) {
            gzclose(f);
            fail(path, "decompresses to more than " + std::to_string(kMaxTextBytes) + " bytes");
        }
        out.append(buf, static_cast<std::size_t>(n));
    }
    // A truncated gzip stream ends without error from gzread on some zlib versions; check.
    int err = 0;
    const char* msg = gzerror(f, &err);
    if (err != Z_OK && err != Z_STREAM_END) {
        const std::string m = msg;
        gzclose(f);
        throw InputError(path + ": read error (" + m + ")");
    }
    if (gzclose(f) != Z_OK) throw InputError(path + ": truncated or corrupt compressed data");
    return out;
}

std::vector<std::string> collect(const std::vector<std::string>& paths) {
    std::vector<std::string> files;
    for (const auto& p : paths) {
        std::error_code ec;
        if (fs::is_directory(p, ec)) {
            std::vector<std::string> here;
            for (const auto& e : fs::directory_iterator(p)) {
                const std::string name = e.path().filename().string();
                if (name == "metadata.json") continue;
                if (e.is_regular_file() && (name.size() > 5) &&
                    (name.find(".json") != std::string::npos))
                    here.push_back(e.path().string());
            }
            std::sort(here.begin(), here.end());
            files.insert(files.end(), here.begin(), here.end());
        } else if (fs::exists(p, ec)) {
            files.push_back(p);
        } else {
            throw InputError(p + ": no such file or directory");
        }
    }
    return files;
}

Metadata Metadata::load(const std::string& path) {
    Metadata m;
    try {
        m.root_ = json::parse(read_text(path));
    } catch (const json::exception& e) {
        throw InputError(path + ": malformed JSON (" + e.what() + ")");
    }
    if (!m.root_.is_object() || !m.root_.contains("opcodes") || !m.root_["opcodes"].is_object())
        throw InputError(path + ": no \"opcodes\" object");
    return m;
}

OpcodeInfo Metadata::lookup(const std::string& stem) const {
    OpcodeInfo info;
    if (root_.is_null()) return info;
    std::string op = stem, reg;
    if (const auto dot = stem.find('.'); dot != std::string::npos) {
        op = stem.substr(0, dot);
        reg = stem.substr(dot + 1);
    }
    std::transform(op.begin(), op.end(), op.begin(), ::toupper);
    const json& ops = root_["opcodes"];
    if (!ops.contains(op)) return info;
    const json* e = &ops[op];
    if (!reg.empty() && e->contains("reg") && (*e)["reg"].contains(reg)) e = &(*e)["reg"][reg];
    if (e->contains("status") && (*e)["status"].is_string()) {
        info.status = (*e)["status"].get<std::string>();
    } else if (reg.empty() && e->contains("reg") && (*e)["reg"].is_object()) {
        info.by_reg = true;
        info.status = "by reg";
        for (unsigned r = 0; r < 8; ++r) {
            const std::string key = std::to_string(r);
            const json& regs = (*e)["reg"];
            if (regs.contains(key) && regs[key].contains("status") && regs[key]["status"].is_string())
                info.reg_status[r] = regs[key]["status"].get<std::string>();
            else
                info.reg_status[r] = "unknown";
        }
    }
    if (e->contains("flags-mask") && (*e)["flags-mask"].is_number_unsigned())
        info.flags_mask = static_cast<std::uint16_t>((*e)["flags-mask"].get<unsigned>());
    return info;
}

OpcodeInfo Metadata::lookup_file(const std::string& path) const { return lookup(stem_of(path)); }

// ---------------------------------------------------------------------------------------------

namespace {

// The reg field of the byte after the prefixes and the opcode of a test's "bytes" (-1 when the
// instruction ends before it).
int modrm_reg(const json& bytes, const std::string& file, const std::string& where) {
    std::size_t i = 0;
    auto at = [&](std::size_t k) { return get_u32(bytes[k], file, where + ".bytes", 0xFF); };
    while (i < bytes.size()) {
        const std::uint32_t b = at(i);
        const bool prefix = (b & 0xE7) == 0x26 || (b & 0xFC) == 0xF0; // ES/CS/SS/DS; LOCK, REP
        if (!prefix) break;
        ++i;
    }
    if (i + 1 >= bytes.size()) return -1;
    return int((at(i + 1) >> 3) & 7);
}

void parse_regs(const json& j, const std::string& file, const std::string& where, std::uint16_t* vals,
                bool* present, bool require_all) {
    if (!j.is_object()) fail(file, where + " is not an object");
    for (auto it = j.begin(); it != j.end(); ++it) {
        int slot = -1;
        for (int i = 0; i < 8; ++i)
            if (it.key() == kRegNames[i]) slot = i;
        for (int i = 0; i < 4; ++i)
            if (it.key() == kSegNames[i]) slot = 8 + i;
        if (it.key() == "ip") slot = 12;
        if (it.key() == "flags") slot = 13;
        if (slot < 0) fail(file, where + ": unknown register \"" + it.key() + "\"");
        vals[slot] = static_cast<std::uint16_t>(get_u32(it.value(), file, where + "." + it.key(), 0xFFFF));
        present[slot] = true;
    }
    if (require_all)
        for (int i = 0; i < 14; ++i)
            if (!present[i]) fail(file, where + ": missing register");
}

void parse_ram(const json& j, const std::string& file, const std::string& where,
               std::vector<std::pair<std::uint32_t, std::uint8_t>>& out) {
    if (!j.is_array()) fail(file, where + " is not an array");
    for (const auto& e : j) {
        if (!e.is_array() || e.size() != 2) fail(file, where + ": entry is not [address, value]: " + e.dump());
        out.emplace_back(get_u32(e[0], file, where + " address", kRamSize - 1),
                         static_cast<std::uint8_t>(get_u32(e[1], file, where + " value", 0xFF)));
    }
}

void check_keys(const json& j, const std::string& file, const std::string& where,
                std::initializer_list<const char*> allowed) {
    for (auto it = j.begin(); it != j.end(); ++it) {
        bool ok = false;
        for (const char* a : allowed) ok = ok || it.key() == a;
        if (!ok) fail(file, where + ": unknown field \"" + it.key() + "\"");
    }
}

const char* qop_name(QueueOp q) {
    switch (q) {
    case QueueOp::first: return "F";
    case QueueOp::subsequent: return "S";
    case QueueOp::flush: return "E";
    default: return "-";
    }
}

// One trace row in a fixed layout: ALE+address, bus status, T-state, queue op+byte, data.
std::string row(bool ale, std::uint32_t addr, const std::string& status, const std::string& t,
                const std::string& qop, unsigned qbyte, bool show_data, std::uint16_t data) {
    std::string s = ale ? "A:" + hex(addr, 5) : "       ";
    s += " " + status + std::string(5 - std::min<std::size_t>(5, status.size()), ' ');
    s += t + std::string(3 - std::min<std::size_t>(3, t.size()), ' ');
    s += qop + (qop != "-" ? hex(qbyte, 2) : std::string("  "));
    s += show_data ? " D:" + hex(data, 4) : std::string("       ");
    return s;
}

} // namespace

unsigned Runner::Harness::bus_access(Bus kind, std::uint32_t address, std::uint16_t& data, unsigned width,
                                     cycles_t start) {
    const unsigned waits = max_waits ? (address ^ (address >> 3) ^ unsigned(kind)) % (max_waits + 1) : 0;
    answer(kind, address, data, width);
    if (log) log->push_back(BusRecord{kind, address, data, std::uint8_t(width), waits, start});
    return waits;
}

void Runner::Harness::answer(Bus kind, std::uint32_t address, std::uint16_t& data, unsigned width) {
    const std::uint32_t a1 = (address + 1) & (kRamSize - 1);
    switch (kind) {
    case Bus::code_fetch: {
        auto next = [&](std::uint32_t a) -> std::uint8_t {
            if (code_left == 0) return kFill;
            --code_left;
            return ram[a];
        };
        const std::uint8_t lo = next(address);
        data = width == 2 ? std::uint16_t(lo | (next(a1) << 8)) : lo;
        break;
    }
    case Bus::mem_read:
        data = width == 2 ? std::uint16_t(ram[address] | (ram[a1] << 8)) : ram[address];
        break;
    case Bus::mem_write:
        ram[address] = std::uint8_t(data);
        if (width == 2) ram[a1] = std::uint8_t(data >> 8);
        break;
    default: // no I/O or INTA device in the suite: the bus floats
        if (kind != Bus::io_write) data = 0xFFFF;
        break;
    }
}

Runner::Runner() : ram_(new std::uint8_t[kRamSize]) {
    std::memset(ram_.get(), kFill, kRamSize);
    // No direct memory map: every bus cycle goes through the harness model.
    harness_.ram = ram_.get();
    cpu_.set_bus_handler(&harness_);
    cpu_.set_bus_hook(
        [](void* ctx, const BusRecord& rec) {
            if (rec.kind == Bus::mem_write) {
                auto* self = static_cast<Runner*>(ctx);
                self->touched_.push_back(rec.address);
                self->touched_.push_back((rec.address + 1) & (kRamSize - 1));
            }
        },
        this);
}

FileResult Runner::run_file(const std::string& path, const Metadata& meta, const std::string& only) {
    FileResult result;
    result.path = path;
    result.stem = stem_of(path);
    const OpcodeInfo info = meta.lookup(result.stem);
    result.status = info.status;
    json tests;
    try {
        tests = json::parse(read_text(path));
    } catch (const json::exception& e) {
        throw InputError(path + ": malformed or truncated JSON (" + e.what() + ")");
    }
    if (!tests.is_array()) throw InputError(path + ": top level is not an array of tests");
    std::vector<Test> list = convert(tests, path);
    if (info.by_reg && !only.empty()) { // the tests of status `only`, the stem with their reg values
        list = tests_of_status(std::move(list), info, only);
        result.status = only;
        for (unsigned r = 0; r < 8; ++r)
            if (info.reg_status[r] == only) result.stem += "/" + std::to_string(r);
    }
    const std::uint64_t c0 = cpu_.cycles();
    for (const Test& t : list) run_one(t, info, &result, true);
    result.tests = list.size();
    result.cycles = cpu_.cycles() - c0;
    return result;
}

std::vector<Test> tests_of_status(std::vector<Test> tests, const OpcodeInfo& info, const std::string& status) {
    tests.erase(std::remove_if(tests.begin(), tests.end(),
                               [&](const Test& t) { return info.status_of(t.modrm_reg) != status; }),
                tests.end());
    return tests;
}

std::uint64_t Runner::run_converted(const std::vector<Test>& tests) {
    const std::uint64_t c0 = cpu_.cycles();
    for (const Test& t : tests) run_one(t, OpcodeInfo{}, nullptr, false);
    return cpu_.cycles() - c0;
}

std::vector<Test> Runner::convert(const json& tests, const std::string& file) {
    std::vector<Test> out;
    std::size_t n = 0;
    for (const auto& j : tests) {
        const std::string where = "test " + std::to_string(n);
        if (!j.is_object()) fail(file, where + " is not an object");
        check_keys(j, file, where, {"name", "bytes", "initial", "final", "cycles", "hash", "idx", "test_hash", "test_num"});
        for (const char* k : {"initial", "final"})
            if (!j.contains(k) || !j[k].is_object()) fail(file, where + ": missing \"" + std::string(k) + "\"");
        Test t;
        t.idx = n;
        t.name = j.contains("name") && j["name"].is_string() ? j["name"].get<std::string>() : "?";
        const json& ini = j["initial"];
        const json& fin = j["final"];
        check_keys(ini, file, where + ".initial", {"regs", "ram", "queue"});
        check_keys(fin, file, where + ".final", {"regs", "ram", "queue"});
        for (const char* k : {"regs", "ram"}) {
            if (!ini.contains(k)) fail(file, where + ".initial: missing \"" + std::string(k) + "\"");
            if (!fin.contains(k)) fail(file, where + ".final: missing \"" + std::string(k) + "\"");
        }
        std::uint16_t iv[14] = {};
        bool ip[14] = {};
        parse_regs(ini["regs"], file, where + ".initial.regs", iv, ip, true);
        for (int i = 0; i < 8; ++i) t.init.r[i] = iv[i];
        for (int i = 0; i < 4; ++i) t.init.s[i] = iv[8 + i];
        t.init.ip = iv[12];
        t.init.flags = iv[13];
        parse_regs(fin["regs"], file, where + ".final.regs", t.fin, t.fin_present, false);
        parse_ram(ini["ram"], file, where + ".initial.ram", t.ram_in);
        parse_ram(fin["ram"], file, where + ".final.ram", t.ram_out);
        if (j.contains("bytes")) {
            if (!j["bytes"].is_array()) fail(file, where + ".bytes is not an array");
            t.code_bytes = j["bytes"].size();
            t.modrm_reg = modrm_reg(j["bytes"], file, where);
        }
        if (ini.contains("queue")) {
            if (!ini["queue"].is_array() || ini["queue"].size() > 6)
                fail(file, where + ".initial.queue is not an array of at most 6 bytes");
            for (const auto& b : ini["queue"])
                t.queue.push_back(static_cast<std::uint8_t>(get_u32(b, file, where + ".initial.queue", 0xFF)));
        }
        if (j.contains("cycles")) {
            if (!j["cycles"].is_array()) fail(file, where + ".cycles is not an array");
            for (const auto& c : j["cycles"])
                if (!c.is_array() || c.size() != 11 || !c[7].is_string() || !c[8].is_string() ||
                    !c[9].is_string() || !c[0].is_number() || !c[1].is_number() || !c[5].is_number() ||
                    !c[6].is_number() || !c[10].is_number())
                    fail(file, where + ".cycles: malformed cycle entry " + c.dump());
            t.cycles = &j["cycles"];
        }
        out.push_back(std::move(t));
        ++n;
    }
    return out;
}

std::vector<Runner::Timing> Runner::timing_per_test(const std::vector<Test>& tests, bool trace, unsigned max_waits) {
    std::vector<Timing> out(tests.size());
    harness_.max_waits = max_waits;
    for (std::size_t i = 0; i < tests.size(); ++i) {
        harness_.log = &out[i].bus;
        const cycles_t base = cpu_.cycles(); // (the core's count runs on from test to test)
        out[i].cycles = run_one(tests[i], OpcodeInfo{}, nullptr, trace);
        for (BusRecord& r : out[i].bus) r.start -= base;
    }
    harness_.log = nullptr;
    harness_.max_waits = 0;
    return out;
}

cycles_t Runner::run_one(const Test& t, const OpcodeInfo& info, FileResult* result, bool trace) {
    std::uint8_t* ram = ram_.get();
    touched_.clear();
    for (const auto& [a, v] : t.ram_in) {
        ram[a] = v;
        touched_.push_back(a);
    }
    harness_.code_left = t.code_bytes > t.queue.size() ? t.code_bytes - t.queue.size() : 0;
    cpu_.load_state(t.init, t.queue.data(), static_cast<unsigned>(t.queue.size()));
    cpu_.set_cycle_trace(nullptr);
    cpu_.start(); // the first byte is read in the clock before the trace begins
    trace_.clear();
    if (trace) cpu_.set_cycle_trace(&trace_);
    const cycles_t c0 = cpu_.cycles();
    cpu_.step();
    const cycles_t used = cpu_.cycles() - c0;
    cpu_.set_cycle_trace(nullptr);

    if (result) {
        auto record = [&](int level, bool ok, const std::string& why) {
            if (ok) ++result->pass[level];
            else if (result->first_failure[level].empty())
                result->first_failure[level] = "test " + std::to_string(t.idx) + " (" + t.name + "): " + why;
        };
        std::string why;
        record(1, check_state(t, info, &why), why);
        if (t.cycles) {
            const json& cyc = *t.cycles;
            record(2, cyc.size() == used,
                   "expected " + std::to_string(cyc.size()) + " cycles, got " + std::to_string(used));
            why.clear();
            const bool ok3 = trace && check_trace(cyc, &why);
            record(3, ok3, why);
            const bool failed = diff_level_ == 2 ? cyc.size() != used : !ok3;
            if (trace && failed && result->diffs.size() < diff_n_) result->diffs.push_back(side_by_side(t, used));
        }
    }

    // Back to the fill pattern for the next test.
    for (std::uint32_t a : touched_) ram[a] = kFill;
    for (const auto& [a, v] : t.ram_out) ram[a] = kFill;
    return used;
}

// Level 1: final registers (undefined flags masked) and the listed RAM.
bool Runner::check_state(const Test& t, const OpcodeInfo& info, std::string* why) const {
    const std::uint8_t* ram = ram_.get();
    const Registers& r = cpu_.regs();
    std::uint16_t got[14], init[14];
    for (int i = 0; i < 8; ++i) got[i] = r.r[i], init[i] = t.init.r[i];
    for (int i = 0; i < 4; ++i) got[8 + i] = r.s[i], init[8 + i] = t.init.s[i];
    got[12] = r.ip, init[12] = t.init.ip;
    got[13] = r.flags, init[13] = t.init.flags;
    std::ostringstream w;
    for (int i = 0; i < 14; ++i) {
        std::uint16_t want = t.fin_present[i] ? t.fin[i] : init[i];
        std::uint16_t have = got[i];
        if (i == 13) {
            want &= info.flags_mask;
            have &= info.flags_mask;
        }
        if (want != have) {
            const char* name = i < 8 ? kRegNames[i] : i < 12 ? kSegNames[i - 8] : i == 12 ? "ip" : "flags";
            w << name << " expected " << want << " got " << have;
            *why = w.str();
            return false;
        }
    }
    // The flags image pushed by a divide error holds the undefined flags: mask it too.
    std::uint32_t flag_img = ~0u;
    const std::uint16_t fin_sp = t.fin_present[SP] ? t.fin[SP] : t.init.r[SP];
    if (info.flags_mask != 0xFFFF && fin_sp == std::uint16_t(t.init.r[SP] - 6))
        flag_img = Cpu::linear(t.init.s[SS], std::uint16_t(t.init.r[SP] - 2));
    for (const auto& [a, v] : t.ram_out) {
        std::uint8_t mask = 0xFF;
        if (a == flag_img) mask = std::uint8_t(info.flags_mask);
        if (a == ((flag_img + 1) & (kRamSize - 1)) && flag_img != ~0u) mask = std::uint8_t(info.flags_mask >> 8);
        if ((ram[a] & mask) != (v & mask)) {
            w << "ram[" << a << "] expected " << unsigned(v) << " got " << unsigned(ram[a]);
            *why = w.str();
            return false;
        }
    }
    return true;
}

// Level 3: per cycle the bus status, T-state, queue operation and byte, ALE and the latched
// address, and on a transfer clock the data on the lanes A0/BHE select.
bool Runner::check_trace(const json& cyc, std::string* why) const {
    std::ostringstream w;
    if (cyc.size() != trace_.size()) {
        w << "length expected " << cyc.size() << " got " << trace_.size();
        *why = w.str();
        return false;
    }
    std::uint32_t latch = 0;
    std::string kind = "PASV";
    for (std::size_t k = 0; k < cyc.size(); ++k) {
        const json& e = cyc[k];
        const CycleRecord& m = trace_[k];
        const bool ale = e[0].get<unsigned>() & 1;
        const std::string status = e[7].get<std::string>();
        const std::string ts = e[8].get<std::string>();
        const std::string qo = e[9].get<std::string>();
        if (ale) {
            latch = e[1].get<std::uint32_t>();
            kind = status;
        }
        auto bad = [&](const char* field, const std::string& want, const std::string& have) {
            w << "cycle " << k << " " << field << " expected " << want << " got " << have;
            *why = w.str();
            return false;
        };
        if (status != to_string(m.status)) return bad("status", status, to_string(m.status));
        if (ts != to_string(m.t)) return bad("T-state", ts, to_string(m.t));
        if (qo != qop_name(m.qop)) return bad("queue op", qo, qop_name(m.qop));
        if (qo != "-" && e[10].get<unsigned>() != m.qbyte)
            return bad("queue byte", std::to_string(e[10].get<unsigned>()), std::to_string(m.qbyte));
        if (ale != m.ale) return bad("ALE", std::to_string(ale), std::to_string(m.ale));
        if (ale && latch != m.address_latch)
            return bad("address", std::to_string(latch), std::to_string(m.address_latch));
        const bool transfer = (ts == "T3" || ts == "Tw") &&
                              (k + 1 >= cyc.size() || cyc[k + 1][8].get<std::string>() != "Tw");
        if (transfer && kind != "PASV" && kind != "HALT") {
            const bool bhe_active = e[5].get<unsigned>() == 0;
            const std::uint16_t lanes = (latch & 1) ? 0xFF00 : bhe_active ? 0xFFFF : 0x00FF;
            const std::uint16_t want = std::uint16_t(e[6].get<unsigned>() & lanes);
            const std::uint16_t have = std::uint16_t(m.data & lanes);
            if (want != have) return bad("data", std::to_string(want), std::to_string(have));
        }
    }
    return true;
}

// The expected and the emulated trace side by side, the first differing row marked.
std::string Runner::side_by_side(const Test& t, cycles_t used) const {
    const json& cyc = *t.cycles;
    std::ostringstream d;
    d << "test " << t.idx << " (" << t.name << ") bytes at " << hex(Cpu::linear(t.init.s[CS], t.init.ip), 5)
      << ", queue " << t.queue.size() << ", expected " << cyc.size() << " cycles, got " << used << "\n";
    const std::size_t n = std::max<std::size_t>(cyc.size(), trace_.size());
    bool marked = false;
    for (std::size_t k = 0; k < n; ++k) {
        std::string a, b;
        if (k < cyc.size()) {
            const json& e = cyc[k];
            const std::string ts = e[8].get<std::string>();
            a = row(e[0].get<unsigned>() & 1, e[1].get<std::uint32_t>(), e[7].get<std::string>(), ts,
                    e[9].get<std::string>(), e[10].get<unsigned>(), ts == "T3" || ts == "Tw",
                    std::uint16_t(e[6].get<unsigned>()));
        }
        if (k < trace_.size()) {
            const CycleRecord& m = trace_[k];
            b = row(m.ale, m.address_latch, to_string(m.status), to_string(m.t), qop_name(m.qop), m.qbyte,
                    m.transfer, m.data);
        }
        // Compare on the fields level 3 checks (data only roughly: lanes are not masked here).
        const bool differ = a.substr(0, std::min<std::size_t>(a.size(), 24)) != b.substr(0, std::min<std::size_t>(b.size(), 24));
        char line[160];
        std::snprintf(line, sizeof line, "  %3zu %-38s | %-38s%s\n", k, a.c_str(), b.c_str(),
                      differ && !marked ? "  <==" : "");
        if (differ) marked = true;
        d << line;
    }
    return d.str();
}

} // namespace rcsim::i8086::sst
