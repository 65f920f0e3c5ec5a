// rcsim — the gdb Remote Serial Protocol on the simulated 8086: packet framing and the packets
// of a stopped target (plain C++; the socket and the simulation are in gdb_stub.h).
//
// Documentation: "Debugging with GDB", appendix E "GDB Remote Serial Protocol" (packets, stop
// replies, qXfer:features, qRcmd) and appendix G "Target Descriptions" (the i386 core feature).
//
// Register convention (docs/tools.md "gdb"): the i386 core layout, 16 registers of 32 bits,
// eax ecx edx ebx esp ebp esi edi eip eflags cs ss ds es fs gs. The 16-bit 8086 registers are
// zero-extended; eip is the linear address CS*16+IP (gdb's breakpoints, `x/i $pc` and the ELF
// symbols are linear); a write of eip keeps CS when the new address is inside CS's 64 KB window
// (IP = linear - CS*16), otherwise sets CS = linear >> 4, IP = linear & 0xF. fs and gs read 0
// (the 8086 has none) and ignore writes; the x87 registers of the layout are unavailable.
#pragma once

#include "comm_cpu/i8086/cpu.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rcsim::debug {

// ---- framing ----

/// "$payload#xx" with the modulo-256 checksum; '#', '$', '}' and '*' escaped ('}' then c ^ 0x20).
std::string rsp_frame(std::string_view payload);
std::string to_hex(std::string_view bytes);

/// Splits the byte stream from gdb into packets. Outside a packet: '+'/'-' acknowledgements are
/// dropped, 0x03 is an interrupt request (Ctrl-C), any other byte is line noise and ignored.
class RspDecoder {
public:
    struct Event {
        enum class Kind { packet, bad_packet, interrupt } kind;
        std::string payload; // packet: unescaped; bad_packet: what was wrong
    };
    static constexpr std::size_t kMaxPacket = 16384; // a longer one is dropped as bad_packet

    void feed(const char* data, std::size_t n, std::vector<Event>& out);

private:
    enum class State { idle, body, escape, sum1, sum2 } state_ = State::idle;
    std::string body_;
    unsigned sum_ = 0;
    char sum_hi_ = 0;
    bool overflow_ = false;
};

// ---- the target as the stub sees it ----

class DebugTarget {
public:
    virtual ~DebugTarget() = default;
    virtual i8086::Registers registers() const = 0;
    virtual void set_registers(const i8086::Registers& r) = 0;
    /// Debugger memory access through the board's memory map without I/O side effects; false
    /// when some byte of the range is not memory.
    virtual bool read_memory(std::uint32_t linear, std::uint8_t* out, std::size_t n) = 0;
    virtual bool write_memory(std::uint32_t linear, const std::uint8_t* in, std::size_t n) = 0;
    /// A `monitor` command's output (text ending in a newline).
    virtual std::string monitor(const std::string& command) = 0;
};

/// Why the target stopped, for the stop reply.
struct StopReason {
    enum class Kind { step, breakpoint, interrupt, watch, exited } kind = Kind::step;
    bool hardware = false;          // breakpoint: a Z1 (hwbreak), else Z0 (swbreak)
    int watch_type = 2;             // watch: 2 write, 3 read, 4 access (the Z number)
    std::uint32_t watch_address = 0;
    int exit_code = 0;
};

/// The packets of one connection (appendix E). handle() answers one packet received while the
/// target is stopped; a resume packet (c, s, D, k) says so in Reply::resume.
class GdbSession {
public:
    enum class Resume { none, step, cont, detach, kill };
    struct Reply {
        std::string payload; // sent framed unless `silent`
        bool silent = false;
        Resume resume = Resume::none;
    };

    explicit GdbSession(DebugTarget& target) : target_(target) {}

    // Limits (docs/tools.md "gdb"): breakpoints are compared at every instruction and
    // watchpoints at every data bus cycle, so their number is bounded; a Z beyond it answers
    // E0e. No reply is longer than kMaxReply (an `m` of 4 KB is 8 KB of hex).
    static constexpr std::size_t kMaxBreakpoints = 64, kMaxWatchpoints = 16;
    static constexpr std::size_t kMaxReply = 16384;
    static constexpr std::uint32_t kMaxWatchLength = 0x100000; // the 8086's whole address space

    Reply handle(const std::string& packet);
    static std::string stop_reply(const StopReason& why);
    void set_last_stop(const StopReason& why) { last_stop_ = why; }

    /// A Z0/Z1 at `linear`: 0 none, 1 software, 2 hardware.
    int breakpoint_at(std::uint32_t linear) const;
    /// The first watchpoint a data access of `width` bytes at `linear` (write or read) triggers.
    std::optional<StopReason> watch_hit(std::uint32_t linear, unsigned width, bool write) const;
    bool has_watchpoints() const { return !watches_.empty(); }
    /// Forgets breakpoints and watchpoints (the debugger went away).
    void clear_points();

    /// The target description served as qXfer:features:read:target.xml.
    static const std::string& target_xml();

private:
    struct Point {
        int type; // the Z number 0..4
        std::uint32_t address;
        std::uint32_t length;
    };
    std::string read_registers() const;
    std::string read_register(unsigned n) const;
    bool write_register(unsigned n, std::uint32_t value);
    std::string read_memory(const std::string& args);
    std::string write_memory(const std::string& args);
    std::string point(const std::string& packet);
    std::string query(const std::string& packet);
    std::uint32_t reg32(unsigned n, const i8086::Registers& r) const;

    DebugTarget& target_;
    StopReason last_stop_;
    std::vector<Point> breaks_, watches_;
};

} // namespace rcsim::debug
