// The gdb Remote Serial Protocol layer (scenarios/debug/gdb_protocol.h) against a fake target:
// framing, the register convention, memory, breakpoints and watchpoints, monitor commands.
// Packet formats from "Debugging with GDB", appendix E.
#include "scenarios/debug/gdb_protocol.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

namespace rcsim::debug {
namespace {

using testing::HasSubstr;

struct FakeTarget : DebugTarget {
    i8086::Registers regs;
    std::map<std::uint32_t, std::uint8_t> mem; // only these bytes are memory
    std::string last_monitor;

    i8086::Registers registers() const override { return regs; }
    void set_registers(const i8086::Registers& r) override { regs = r; }
    bool read_memory(std::uint32_t a, std::uint8_t* out, std::size_t n) override {
        for (std::size_t i = 0; i < n; ++i) {
            auto it = mem.find(a + std::uint32_t(i));
            if (it == mem.end()) return false;
            out[i] = it->second;
        }
        return true;
    }
    bool write_memory(std::uint32_t a, const std::uint8_t* in, std::size_t n) override {
        for (std::size_t i = 0; i < n; ++i)
            if (!mem.count(a + std::uint32_t(i))) return false;
        for (std::size_t i = 0; i < n; ++i) mem[a + std::uint32_t(i)] = in[i];
        return true;
    }
    std::string monitor(const std::string& c) override {
        last_monitor = c;
        return "out\n";
    }
};

std::vector<RspDecoder::Event> decode(const std::string& bytes) {
    RspDecoder d;
    std::vector<RspDecoder::Event> ev;
    d.feed(bytes.data(), bytes.size(), ev);
    return ev;
}

// ---- framing ----

TEST(GdbProtocol, FrameChecksumIsTheByteSumModulo256) {
    // 'O' 'K' = 0x4F + 0x4B = 0x9A
    EXPECT_EQ(rsp_frame("OK"), "$OK#9a");
    EXPECT_EQ(rsp_frame(""), "$#00");
    // '#' is sent as '}' then '#' ^ 0x20 = 0x03; the checksum covers the escaped bytes:
    // 0x7D + 0x03 = 0x80.
    EXPECT_EQ(rsp_frame("#"), std::string("$}\x03#80"));
}

TEST(GdbProtocol, DecoderSplitsPacketsAcksAndInterrupts) {
    const auto ev = decode("+$g#67-\x03$m0,4#fd");
    ASSERT_EQ(ev.size(), 3u);
    EXPECT_EQ(ev[0].kind, RspDecoder::Event::Kind::packet);
    EXPECT_EQ(ev[0].payload, "g");
    EXPECT_EQ(ev[1].kind, RspDecoder::Event::Kind::interrupt);
    EXPECT_EQ(ev[2].payload, "m0,4");
    // A payload with every character that must be escaped round-trips.
    const auto back = decode(rsp_frame("a}b#c$d*e"));
    ASSERT_EQ(back.size(), 1u);
    EXPECT_EQ(back[0].payload, "a}b#c$d*e");
}

TEST(GdbProtocol, DecoderReportsGarbageAsBadPackets) {
    auto ev = decode("$g#00");
    ASSERT_EQ(ev.size(), 1u);
    EXPECT_EQ(ev[0].kind, RspDecoder::Event::Kind::bad_packet);
    EXPECT_THAT(ev[0].payload, HasSubstr("checksum"));
    ev = decode("$g#zz");
    ASSERT_EQ(ev.size(), 1u);
    EXPECT_EQ(ev[0].kind, RspDecoder::Event::Kind::bad_packet);
    ev = decode("$abc$g#67"); // a packet cut short by the next one
    ASSERT_EQ(ev.size(), 2u);
    EXPECT_EQ(ev[0].kind, RspDecoder::Event::Kind::bad_packet);
    EXPECT_EQ(ev[1].payload, "g");
    EXPECT_TRUE(decode("hello world\r\n").empty()); // noise outside packets
    const std::string huge = "$" + std::string(RspDecoder::kMaxPacket + 1, 'a') + "#00";
    ev = decode(huge);
    ASSERT_EQ(ev.size(), 1u);
    EXPECT_EQ(ev[0].kind, RspDecoder::Event::Kind::bad_packet);
}

// ---- registers ----

TEST(GdbProtocol, RegistersInTheI386CoreOrderWithALinearEip) {
    FakeTarget t;
    using namespace i8086;
    t.regs.r[AX] = 0x1234;
    t.regs.r[DI] = 0xBEEF;
    t.regs.s[CS] = 0xF000;
    t.regs.ip = 0x024C;
    t.regs.s[DS] = 0x0040;
    t.regs.flags = 0xF202;
    GdbSession s(t);
    const std::string g = s.handle("g").payload;
    ASSERT_EQ(g.size(), 16u * 8); // 16 registers of 4 bytes, 2 hex digits a byte
    EXPECT_EQ(g.substr(0, 8), "34120000");      // eax
    EXPECT_EQ(g.substr(7 * 8, 8), "efbe0000");  // edi
    EXPECT_EQ(g.substr(8 * 8, 8), "4c020f00");  // eip = F000*16 + 024C = F024C
    EXPECT_EQ(g.substr(9 * 8, 8), "02f20000");  // eflags
    EXPECT_EQ(g.substr(10 * 8, 8), "00f00000"); // cs
    EXPECT_EQ(g.substr(12 * 8, 8), "40000000"); // ds
    EXPECT_EQ(g.substr(14 * 8, 8), "00000000"); // fs: none on the 8086
    EXPECT_EQ(s.handle("p8").payload, "4c020f00");
    EXPECT_EQ(s.handle("p10").payload, std::string(20, 'x')); // st0: unavailable, 10 bytes
    EXPECT_EQ(s.handle("p18").payload, std::string(8, 'x'));  // fctrl
}

TEST(GdbProtocol, EipWritesKeepCsInsideItsWindowElseRebaseIt) {
    FakeTarget t;
    using namespace i8086;
    t.regs.s[CS] = 0xF000;
    GdbSession s(t);
    EXPECT_EQ(s.handle("P8=00010f00").payload, "OK"); // F0100: inside F000's window
    EXPECT_EQ(t.regs.s[CS], 0xF000);
    EXPECT_EQ(t.regs.ip, 0x0100);
    EXPECT_EQ(s.handle("P8=34120000").payload, "OK"); // 01234: below CS*16 -> 0123:0004
    EXPECT_EQ(t.regs.s[CS], 0x0123);
    EXPECT_EQ(t.regs.ip, 0x0004);
    EXPECT_EQ(s.handle("P0=cdab").payload, "OK");
    EXPECT_EQ(t.regs.r[AX], 0xABCD);
    EXPECT_EQ(s.handle("Pd=4000").payload, "OK"); // es
    EXPECT_EQ(t.regs.s[ES], 0x0040);
    EXPECT_EQ(s.handle("P10=00").payload, "E01"); // st0
    EXPECT_EQ(s.handle("Pzz=00").payload, "E01");
}

// ---- memory ----

TEST(GdbProtocol, MemoryReadAndWriteAndUnmappedBytes) {
    FakeTarget t;
    for (std::uint32_t a = 0x400; a < 0x404; ++a) t.mem[a] = std::uint8_t(a);
    GdbSession s(t);
    EXPECT_EQ(s.handle("m400,4").payload, "00010203");
    EXPECT_EQ(s.handle("m402,4").payload, "E01"); // 404 is not memory
    EXPECT_EQ(s.handle("M401,2:aabb").payload, "OK");
    EXPECT_EQ(t.mem[0x401], 0xAA);
    EXPECT_EQ(t.mem[0x402], 0xBB);
    EXPECT_EQ(s.handle("M401,2:aa").payload, "E01"); // length and data disagree
    EXPECT_EQ(s.handle("mxyz").payload, "E01");
}

// ---- breakpoints, watchpoints, stop replies ----

TEST(GdbProtocol, BreakpointsAndWatchpoints) {
    FakeTarget t;
    GdbSession s(t);
    EXPECT_EQ(s.handle("Z0,f024c,1").payload, "OK");
    EXPECT_EQ(s.handle("Z1,f0300,1").payload, "OK");
    EXPECT_EQ(s.breakpoint_at(0xF024C), 1);
    EXPECT_EQ(s.breakpoint_at(0xF0300), 2);
    EXPECT_EQ(s.breakpoint_at(0xF024D), 0);
    EXPECT_EQ(s.handle("z0,f024c,1").payload, "OK");
    EXPECT_EQ(s.breakpoint_at(0xF024C), 0);

    EXPECT_FALSE(s.has_watchpoints());
    EXPECT_EQ(s.handle("Z2,488,2").payload, "OK"); // write watch on 488-489
    EXPECT_EQ(s.handle("Z3,500,1").payload, "OK"); // read watch on 500
    EXPECT_TRUE(s.has_watchpoints());
    EXPECT_FALSE(s.watch_hit(0x488, 2, false)); // a read does not trigger a write watch
    EXPECT_FALSE(s.watch_hit(0x486, 2, true));  // 486-487: just below
    auto hit = s.watch_hit(0x489, 1, true);
    ASSERT_TRUE(hit);
    EXPECT_EQ(GdbSession::stop_reply(*hit), "T05watch:489;");
    hit = s.watch_hit(0x4FF, 2, false); // a word read over 4FF-500
    ASSERT_TRUE(hit);
    EXPECT_EQ(GdbSession::stop_reply(*hit), "T05rwatch:500;");
    EXPECT_EQ(s.handle("Z4,600,1").payload, "OK");
    EXPECT_EQ(GdbSession::stop_reply(*s.watch_hit(0x600, 1, true)), "T05awatch:600;");
    s.clear_points();
    EXPECT_FALSE(s.watch_hit(0x600, 1, true));
    EXPECT_EQ(s.handle("Z9,600,1").payload, ""); // unknown type: unsupported
}

TEST(GdbProtocol, PointsAreBoundedAndIdempotent) {
    // Each point is compared at every instruction or data bus cycle: their number is bounded
    // (docs/tools.md "gdb", limits), and inserting one twice keeps one (appendix E: Z is
    // idempotent).
    FakeTarget t;
    GdbSession s(t);
    EXPECT_EQ(s.handle("Z0,100,1").payload, "OK");
    EXPECT_EQ(s.handle("Z0,100,1").payload, "OK");
    EXPECT_EQ(s.handle("z0,100,1").payload, "OK");
    EXPECT_EQ(s.breakpoint_at(0x100), 0);
    for (unsigned i = 0; i < GdbSession::kMaxBreakpoints; ++i)
        ASSERT_EQ(s.handle("Z0," + std::to_string(1000 + i) + ",1").payload, "OK") << i;
    EXPECT_EQ(s.handle("Z1,f0000,1").payload, "E0e");
    EXPECT_EQ(s.handle("z0,1000,1").payload, "OK");
    EXPECT_EQ(s.handle("Z1,f0000,1").payload, "OK");
    for (unsigned i = 0; i < GdbSession::kMaxWatchpoints; ++i)
        ASSERT_EQ(s.handle("Z2," + std::to_string(1000 + i) + ",2").payload, "OK") << i;
    EXPECT_EQ(s.handle("Z4,f0000,1").payload, "E0e");
    // A watched range is inside the 1 MB address space: a longer one is refused, not wrapped.
    s.clear_points();
    EXPECT_EQ(s.handle("Z2,0,ffffffff").payload, "E01");
    EXPECT_EQ(s.handle("Z3,fffff,100001").payload, "E01");
    EXPECT_FALSE(s.has_watchpoints());
    EXPECT_EQ(s.handle("Z3,0,100000").payload, "OK");
    EXPECT_TRUE(s.watch_hit(0xFFFFF, 1, false));
}

TEST(GdbProtocol, RandomPacketsGetBoundedRepliesAndNeverCrash) {
    // A seeded fuzz of the packet layer: every packet letter with random arguments, and random
    // bytes. The replies stay within the advertised PacketSize and the points stay bounded.
    FakeTarget t;
    for (std::uint32_t a = 0; a < 0x2000; ++a) t.mem[a] = std::uint8_t(a);
    GdbSession s(t);
    std::mt19937 rng(33);
    const std::string letters = "?gGpPmMzZqHTcsvX!", args = "0123456789abcdefABCDEF,:=;xz-}#";
    for (int i = 0; i < 20000; ++i) {
        std::string p(1, letters[rng() % letters.size()]);
        if (p == "q" && rng() % 2) p = rng() % 2 ? "qXfer:features:read:target.xml:" : "qRcmd,";
        const std::size_t n = rng() % 24;
        for (std::size_t k = 0; k < n; ++k)
            p += rng() % 8 ? args[rng() % args.size()] : char(rng() % 256);
        const auto r = s.handle(p);
        ASSERT_LE(r.payload.size(), GdbSession::kMaxReply) << p;
    }
    RspDecoder d;
    std::vector<RspDecoder::Event> ev;
    std::string bytes;
    for (int i = 0; i < 200000; ++i) bytes += char(rng() % 4 ? "$#}x03+-a"[rng() % 9] : rng() % 256);
    for (std::size_t at = 0; at < bytes.size();) {
        const std::size_t n = std::min<std::size_t>(1 + rng() % 5000, bytes.size() - at);
        d.feed(bytes.data() + at, n, ev);
        at += n;
    }
    EXPECT_LE(ev.size(), bytes.size());
    for (const auto& e : ev) EXPECT_LE(e.payload.size(), RspDecoder::kMaxPacket);
}

TEST(GdbProtocol, StopRepliesAndResumePackets) {
    FakeTarget t;
    GdbSession s(t);
    StopReason r;
    EXPECT_EQ(GdbSession::stop_reply(r), "T05");
    r.kind = StopReason::Kind::breakpoint;
    EXPECT_EQ(GdbSession::stop_reply(r), "T05swbreak:;");
    r.hardware = true;
    EXPECT_EQ(GdbSession::stop_reply(r), "T05hwbreak:;");
    r.kind = StopReason::Kind::interrupt;
    EXPECT_EQ(GdbSession::stop_reply(r), "T02"); // SIGINT
    r.kind = StopReason::Kind::exited;
    r.exit_code = 1;
    EXPECT_EQ(GdbSession::stop_reply(r), "W01");
    s.set_last_stop(StopReason{StopReason::Kind::interrupt});
    EXPECT_EQ(s.handle("?").payload, "T02");
    EXPECT_EQ(s.handle("c").resume, GdbSession::Resume::cont);
    EXPECT_TRUE(s.handle("c").silent);
    EXPECT_EQ(s.handle("s").resume, GdbSession::Resume::step);
    EXPECT_EQ(s.handle("D").resume, GdbSession::Resume::detach);
    EXPECT_EQ(s.handle("k").resume, GdbSession::Resume::kill);
    EXPECT_EQ(s.handle("vCont?").payload, ""); // gdb falls back to s and c
    EXPECT_EQ(s.handle("Xgarbage").payload, "");
}

// ---- queries ----

TEST(GdbProtocol, TargetXmlInChunksAndMonitorCommands) {
    FakeTarget t;
    GdbSession s(t);
    EXPECT_THAT(s.handle("qSupported:multiprocess+;swbreak+").payload, HasSubstr("qXfer:features:read+"));
    const std::string& xml = GdbSession::target_xml();
    std::string got;
    for (std::size_t off = 0;;) {
        char q[80];
        std::snprintf(q, sizeof q, "qXfer:features:read:target.xml:%zx,100", off);
        const std::string r = s.handle(q).payload;
        ASSERT_FALSE(r.empty());
        got += r.substr(1);
        off += r.size() - 1;
        if (r[0] == 'l') break;
        ASSERT_EQ(r[0], 'm');
    }
    EXPECT_EQ(got, xml);
    EXPECT_THAT(xml, HasSubstr("<architecture>i8086</architecture>"));
    EXPECT_THAT(xml, HasSubstr("org.gnu.gdb.i386.core"));
    EXPECT_EQ(s.handle("qXfer:features:read:other.xml:0,100").payload, "E00");
    // qRcmd,<hex of "time"> -> hex of the output
    EXPECT_EQ(s.handle("qRcmd," + to_hex("time")).payload, to_hex("out\n"));
    EXPECT_EQ(t.last_monitor, "time");
    EXPECT_EQ(s.handle("qRcmd,zz").payload, "E01");
}

} // namespace
} // namespace rcsim::debug
