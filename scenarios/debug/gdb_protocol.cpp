// rcsim — gdb Remote Serial Protocol packets (gdb_protocol.h).
#include "scenarios/debug/gdb_protocol.h"

#include "models/plumbing/hex.h"

#include <algorithm>
#include <cstdio>

namespace rcsim::debug {

namespace {

int hex_value(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}


/// A hex number of at most 8 digits filling all of `s`.
std::optional<std::uint32_t> parse_number(std::string_view s) {
    if (s.empty() || s.size() > 8) return std::nullopt;
    std::uint32_t v = 0;
    for (char c : s) {
        const int d = hex_value(c);
        if (d < 0) return std::nullopt;
        v = v << 4 | unsigned(d);
    }
    return v;
}

/// "addr,len" (hex) from `s`; nullopt when malformed.
std::optional<std::pair<std::uint32_t, std::uint32_t>> parse_range(std::string_view s) {
    const auto comma = s.find(',');
    if (comma == std::string_view::npos) return std::nullopt;
    const auto a = parse_number(s.substr(0, comma)), n = parse_number(s.substr(comma + 1));
    if (!a || !n) return std::nullopt;
    return std::make_pair(*a, *n);
}

bool parse_bytes(std::string_view hex, std::vector<std::uint8_t>& out) {
    if (hex.size() % 2) return false;
    out.clear();
    for (std::size_t i = 0; i < hex.size(); i += 2) {
        const int hi = hex_value(hex[i]), lo = hex_value(hex[i + 1]);
        if (hi < 0 || lo < 0) return false;
        out.push_back(std::uint8_t(hi << 4 | lo));
    }
    return true;
}

/// A byte in the two lower-case hex digits of the protocol.
std::string hex2(unsigned v) { return hex(v & 0xFF, 2, HexCase::lower); }

/// A 32-bit register as gdb's i386 target sends it: four bytes, least significant first.
std::string le32(std::uint32_t v) {
    std::string s;
    for (int i = 0; i < 4; ++i) s += hex2(v >> (8 * i));
    return s;
}


// The i386 core registers after the 16 integer ones: st0..st7 (80 bits), then fctrl, fstat,
// ftag, fiseg, fioff, foseg, fooff, fop (32 bits), the order of gdb's i386 core feature.
constexpr unsigned kIntRegs = 16, kCoreRegs = 32;
unsigned reg_bytes(unsigned n) { return n >= 16 && n < 24 ? 10 : 4; }

} // namespace

// ---- framing ----

std::string to_hex(std::string_view bytes) {
    std::string s;
    for (unsigned char c : bytes) s += hex2(c);
    return s;
}

std::string rsp_frame(std::string_view payload) {
    std::string out = "$";
    unsigned sum = 0;
    for (char c : payload) {
        if (c == '#' || c == '$' || c == '}' || c == '*') {
            out += '}';
            sum += '}';
            c = char(c ^ 0x20);
        }
        out += c;
        sum += static_cast<unsigned char>(c);
    }
    out += '#';
    out += hex2(sum & 0xFF);
    return out;
}

void RspDecoder::feed(const char* data, std::size_t n, std::vector<Event>& out) {
    for (std::size_t i = 0; i < n; ++i) {
        const char c = data[i];
        switch (state_) {
        case State::idle:
            if (c == '$') {
                body_.clear();
                sum_ = 0;
                overflow_ = false;
                state_ = State::body;
            } else if (c == '\x03') {
                out.push_back({Event::Kind::interrupt, {}});
            } // '+', '-' and noise: nothing to do
            break;
        case State::body:
        case State::escape:
            if (c == '$') { // a new packet before this one ended
                out.push_back({Event::Kind::bad_packet, "a packet without its '#' checksum"});
                body_.clear();
                sum_ = 0;
                overflow_ = false;
                state_ = State::body;
                break;
            }
            if (state_ == State::body && c == '#') {
                state_ = State::sum1;
                break;
            }
            sum_ += static_cast<unsigned char>(c);
            if (state_ == State::body && c == '}') {
                state_ = State::escape;
                break;
            }
            if (body_.size() < kMaxPacket) body_ += state_ == State::escape ? char(c ^ 0x20) : c;
            else overflow_ = true;
            state_ = State::body;
            break;
        case State::sum1:
            sum_hi_ = c;
            state_ = State::sum2;
            break;
        case State::sum2: {
            state_ = State::idle;
            const int hi = hex_value(sum_hi_), lo = hex_value(c);
            if (hi < 0 || lo < 0) out.push_back({Event::Kind::bad_packet, "a checksum that is not two hex digits"});
            else if (unsigned(hi << 4 | lo) != (sum_ & 0xFF)) out.push_back({Event::Kind::bad_packet, "a bad checksum"});
            else if (overflow_) out.push_back({Event::Kind::bad_packet, "a packet longer than 16384 bytes"});
            else out.push_back({Event::Kind::packet, body_});
            break;
        }
        }
    }
}

// ---- registers ----

std::uint32_t GdbSession::reg32(unsigned n, const i8086::Registers& r) const {
    using namespace i8086;
    if (n < 8) return r.r[n]; // AX CX DX BX SP BP SI DI: the i386 order
    switch (n) {
    case 8: return Cpu::linear(r.s[CS], r.ip);
    case 9: return r.flags;
    case 10: return r.s[CS];
    case 11: return r.s[SS];
    case 12: return r.s[DS];
    case 13: return r.s[ES];
    default: return 0; // fs, gs
    }
}

std::string GdbSession::read_registers() const {
    const auto r = target_.registers();
    std::string s;
    for (unsigned n = 0; n < kIntRegs; ++n) s += le32(reg32(n, r));
    return s; // shorter than the layout: gdb takes the x87 registers as unavailable
}

std::string GdbSession::read_register(unsigned n) const {
    if (n < kIntRegs) return le32(reg32(n, target_.registers()));
    if (n < kCoreRegs) return std::string(2 * reg_bytes(n), 'x'); // unavailable
    return "E00";
}

bool GdbSession::write_register(unsigned n, std::uint32_t v) {
    using namespace i8086;
    auto r = target_.registers();
    const auto w = std::uint16_t(v);
    if (n < 8) {
        r.r[n] = w;
    } else if (n == 8) {
        // eip is linear: keep CS when the address is inside its 64 KB window.
        const std::uint32_t base = std::uint32_t(r.s[CS]) << 4;
        const std::uint32_t linear = v & 0xFFFFF;
        if (linear >= base && linear - base <= 0xFFFF) {
            r.ip = std::uint16_t(linear - base);
        } else {
            r.s[CS] = std::uint16_t(linear >> 4);
            r.ip = std::uint16_t(linear & 0xF);
        }
    } else if (n == 9) {
        r.flags = w;
    } else if (n >= 10 && n <= 13) {
        const SReg seg[] = {CS, SS, DS, ES};
        r.s[seg[n - 10]] = w;
    } else if (n == 14 || n == 15) {
        return true; // fs, gs: not on the 8086
    } else {
        return false;
    }
    target_.set_registers(r);
    return true;
}

// ---- memory ----

std::string GdbSession::read_memory(const std::string& args) {
    const auto range = parse_range(args);
    if (!range || range->second > 0x1000) return "E01";
    std::vector<std::uint8_t> buf(range->second);
    if (!target_.read_memory(range->first, buf.data(), buf.size())) return "E01";
    return to_hex(std::string_view(reinterpret_cast<const char*>(buf.data()), buf.size()));
}

std::string GdbSession::write_memory(const std::string& args) {
    const auto colon = args.find(':');
    if (colon == std::string::npos) return "E01";
    const auto range = parse_range(std::string_view(args).substr(0, colon));
    std::vector<std::uint8_t> bytes;
    if (!range || !parse_bytes(std::string_view(args).substr(colon + 1), bytes) || bytes.size() != range->second)
        return "E01";
    return target_.write_memory(range->first, bytes.data(), bytes.size()) ? "OK" : "E01";
}

// ---- breakpoints and watchpoints ----

std::string GdbSession::point(const std::string& packet) {
    // Z<type>,<addr>,<kind> / z<type>,<addr>,<kind>
    if (packet.size() < 2 || packet[1] < '0' || packet[1] > '4' || (packet.size() > 2 && packet[2] != ',')) return "";
    const int type = packet[1] - '0';
    const auto range = parse_range(std::string_view(packet).substr(std::min<std::size_t>(3, packet.size())));
    if (!range) return "E01";
    if (type >= 2 && range->second > kMaxWatchLength) return "E01"; // would wrap around 4 GB
    auto& list = type <= 1 ? breaks_ : watches_;
    const Point p{type, range->first & 0xFFFFF, type <= 1 ? 1 : std::max<std::uint32_t>(range->second, 1)};
    const auto it = std::find_if(list.begin(), list.end(), [&](const Point& q) {
        return q.type == p.type && q.address == p.address && q.length == p.length;
    });
    if (packet[0] == 'z') {
        if (it != list.end()) list.erase(it);
        return "OK";
    }
    if (it != list.end()) return "OK"; // inserting twice is not an error (appendix E)
    if (list.size() >= (type <= 1 ? kMaxBreakpoints : kMaxWatchpoints)) return "E0e";
    list.push_back(p);
    return "OK";
}

int GdbSession::breakpoint_at(std::uint32_t linear) const {
    int found = 0;
    for (const Point& p : breaks_)
        if (p.address == linear) found = p.type == 0 ? 1 : std::max(found, 2);
    return found;
}

std::optional<StopReason> GdbSession::watch_hit(std::uint32_t linear, unsigned width, bool write) const {
    for (const Point& w : watches_) {
        const bool kind = w.type == 4 || (w.type == 2) == write;
        if (!kind || linear + width <= w.address || linear >= w.address + w.length) continue;
        StopReason r;
        r.kind = StopReason::Kind::watch;
        r.watch_type = w.type;
        r.watch_address = std::max(linear, w.address); // the first watched byte accessed
        return r;
    }
    return std::nullopt;
}

void GdbSession::clear_points() {
    breaks_.clear();
    watches_.clear();
}

std::string GdbSession::stop_reply(const StopReason& why) {
    using K = StopReason::Kind;
    switch (why.kind) {
    case K::step: return "T05";
    case K::breakpoint: return why.hardware ? "T05hwbreak:;" : "T05swbreak:;";
    case K::interrupt: return "T02";
    case K::exited: return "W" + hex2(unsigned(why.exit_code) & 0xFF);
    case K::watch: {
        const char* name = why.watch_type == 3 ? "rwatch" : why.watch_type == 4 ? "awatch" : "watch";
        char buf[40];
        std::snprintf(buf, sizeof buf, "T05%s:%x;", name, static_cast<unsigned>(why.watch_address));
        return buf;
    }
    }
    return "T05";
}

// ---- queries ----

std::string GdbSession::query(const std::string& p) {
    if (p.rfind("qSupported", 0) == 0) return "PacketSize=4000;qXfer:features:read+;swbreak+;hwbreak+";
    if (p == "qAttached") return "1"; // gdb detaches (never kills) when it quits
    if (p.rfind("qSymbol:", 0) == 0) return "OK";
    const std::string xfer = "qXfer:features:read:";
    if (p.rfind(xfer, 0) == 0) {
        const auto colon = p.find(':', xfer.size());
        if (colon == std::string::npos || p.substr(xfer.size(), colon - xfer.size()) != "target.xml") return "E00";
        const auto range = parse_range(std::string_view(p).substr(colon + 1));
        if (!range) return "E00";
        const std::string& xml = target_xml();
        if (range->first >= xml.size()) return "l";
        const std::string chunk = xml.substr(range->first, std::min<std::size_t>(range->second, kMaxReply - 1));
        return (range->first + chunk.size() >= xml.size() ? "l" : "m") + chunk;
    }
    if (p.rfind("qRcmd,", 0) == 0) {
        std::vector<std::uint8_t> cmd;
        if (!parse_bytes(std::string_view(p).substr(6), cmd)) return "E01";
        const std::string text = target_.monitor(std::string(cmd.begin(), cmd.end()));
        return to_hex(text);
    }
    return "";
}

GdbSession::Reply GdbSession::handle(const std::string& p) {
    if (p.empty()) return {""};
    switch (p[0]) {
    case '?': return {stop_reply(last_stop_)};
    case 'g': return {read_registers()};
    case 'G': {
        std::vector<std::uint8_t> b;
        if (!parse_bytes(std::string_view(p).substr(1), b) || b.size() < 4 * kIntRegs) return {"E01"};
        for (unsigned n = 0; n < kIntRegs; ++n)
            write_register(n, std::uint32_t(b[4 * n]) | b[4 * n + 1] << 8 | b[4 * n + 2] << 16 | std::uint32_t(b[4 * n + 3]) << 24);
        return {"OK"};
    }
    case 'p': {
        const auto n = parse_number(std::string_view(p).substr(1));
        return {n ? read_register(*n) : "E01"};
    }
    case 'P': {
        const auto eq = p.find('=');
        std::vector<std::uint8_t> b;
        const auto n = eq == std::string::npos ? std::nullopt : parse_number(std::string_view(p).substr(1, eq - 1));
        if (!n || !parse_bytes(std::string_view(p).substr(eq + 1), b) || b.empty() || b.size() > 4) return {"E01"};
        std::uint32_t v = 0;
        for (std::size_t i = 0; i < b.size(); ++i) v |= std::uint32_t(b[i]) << (8 * i);
        return {write_register(*n, v) ? "OK" : "E01"};
    }
    case 'm': return {read_memory(p.substr(1))};
    case 'M': return {write_memory(p.substr(1))};
    case 'Z':
    case 'z': return {point(p)};
    case 'q': return {query(p)};
    case 'H':
    case 'T': return {"OK"}; // one thread
    case 'c':
    case 's': {
        if (p.size() > 1) { // resume at an address
            const auto a = parse_number(std::string_view(p).substr(1));
            if (!a) return {"E01"};
            write_register(8, *a);
        }
        return {"", true, p[0] == 's' ? Resume::step : Resume::cont};
    }
    case 'D': return {"OK", false, Resume::detach};
    case 'k': return {"", true, Resume::kill};
    case 'v':
        if (p.rfind("vKill", 0) == 0) return {"OK", false, Resume::kill};
        return {""}; // vMustReplyEmpty, vCont? (gdb then uses s and c), the rest
    default: return {""};
    }
}

// ---- target description ----

const std::string& GdbSession::target_xml() {
    // The i386 core feature as gdb requires it for an i386-family architecture (the names,
    // order and sizes of its registers); `i8086` selects 16-bit disassembly, and OS ABI `none`
    // keeps a Linux-hosted gdb from assuming a Linux program (no `set osabi` needed).
    static const std::string xml = [] {
        std::string x =
            "<?xml version=\"1.0\"?>\n<!DOCTYPE target SYSTEM \"gdb-target.dtd\">\n<target version=\"1.0\">\n"
            "<architecture>i8086</architecture>\n<osabi>none</osabi>\n<feature name=\"org.gnu.gdb.i386.core\">\n"
            "<flags id=\"i386_eflags\" size=\"4\">\n"
            "<field name=\"CF\" start=\"0\" end=\"0\"/><field name=\"\" start=\"1\" end=\"1\"/>\n"
            "<field name=\"PF\" start=\"2\" end=\"2\"/><field name=\"AF\" start=\"4\" end=\"4\"/>\n"
            "<field name=\"ZF\" start=\"6\" end=\"6\"/><field name=\"SF\" start=\"7\" end=\"7\"/>\n"
            "<field name=\"TF\" start=\"8\" end=\"8\"/><field name=\"IF\" start=\"9\" end=\"9\"/>\n"
            "<field name=\"DF\" start=\"10\" end=\"10\"/><field name=\"OF\" start=\"11\" end=\"11\"/>\n"
            "</flags>\n";
        const char* gpr[] = {"eax", "ecx", "edx", "ebx", "esp", "ebp", "esi", "edi"};
        const char* gpr_type[] = {"int32", "int32", "int32", "int32", "data_ptr", "data_ptr", "int32", "int32"};
        for (int i = 0; i < 8; ++i)
            x += std::string("<reg name=\"") + gpr[i] + "\" bitsize=\"32\" type=\"" + gpr_type[i] + "\"/>\n";
        x += "<reg name=\"eip\" bitsize=\"32\" type=\"code_ptr\"/>\n<reg name=\"eflags\" bitsize=\"32\" type=\"i386_eflags\"/>\n";
        for (const char* s : {"cs", "ss", "ds", "es", "fs", "gs"})
            x += std::string("<reg name=\"") + s + "\" bitsize=\"32\" type=\"int32\"/>\n";
        for (int i = 0; i < 8; ++i)
            x += "<reg name=\"st" + std::to_string(i) + "\" bitsize=\"80\" type=\"i387_ext\"/>\n";
        for (const char* f : {"fctrl", "fstat", "ftag", "fiseg", "fioff", "foseg", "fooff", "fop"})
            x += std::string("<reg name=\"") + f + "\" bitsize=\"32\" type=\"int\" group=\"float\"/>\n";
        x += "</feature>\n</target>\n";
        return x;
    }();
    return xml;
}

} // namespace rcsim::debug
