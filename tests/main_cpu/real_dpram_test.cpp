// The main CPU against the real IDT7130 model (dpram/), with a scripted comm CPU on the left port
// doing real 8 MHz bus cycles: frames cross intact, and BUSY from the arbiter stretches the main
// CPU's accesses by exactly the wait states the model reports.
#include "dpram/idt7130.h"
#include "main_cpu/main_cpu.h"
#include "tests/support/sc_test.h"

#include <gtest/gtest.h>
#include <tlm_utils/simple_initiator_socket.h>

#include <deque>
#include <functional>

using namespace rcsim;
using namespace rcsim::dpram_layout;
using sc_core::sc_time;

namespace {

/// The comm CPU's left-port bus cycles (8 MHz, 4 clocks + BUSY), with the firmware's mailbox
/// handshake: it clears int2ext after reading and writes int2rbt only once it reads 0, polling
/// back to back — which collides with the main CPU's own accesses to 0x3FF.
struct LeftCpu : sc_core::sc_module {
    tlm_utils::simple_initiator_socket<LeftCpu> bus{"bus"};
    sc_core::sc_in<bool> int_l{"int_l"};
    std::function<void(LeftCpu&)> script;
    std::deque<std::uint8_t> pending;
    Clock clk{8'000'000};

    explicit LeftCpu(sc_core::sc_module_name n) : sc_module(n) { test::spawn_checked([this] { run(); }, "run"); }
    void run() {
        if (script) script(*this);
    }

    std::uint8_t access(BusCycle kind, std::uint16_t addr, std::uint8_t v) {
        const BusResult r = bus_access(bus, kind, addr, &v, 1, sc_core::sc_time_stamp(), 0);
        EXPECT_TRUE(r.ok());
        wait(clk.cycles(4 + r.wait_states));
        return v;
    }
    std::uint8_t rd(std::uint16_t a) { return access(BusCycle::mem_read, a, 0); }
    void wr(std::uint16_t a, std::uint8_t v) { access(BusCycle::mem_write, a, v); }

    void post_word(std::uint8_t w) {
        while (rd(int2rbt) != 0) {
        }
        wr(int2rbt, w);
    }
    int next_word(const sc_time& timeout) {
        if (!int_l.read()) wait(timeout, int_l.posedge_event());
        if (!int_l.read()) return -1;
        const std::uint8_t w = rd(int2ext);
        wr(int2ext, 0);
        return w;
    }
    bool expect_word(std::uint8_t want, const sc_time& timeout) {
        for (auto it = pending.begin(); it != pending.end(); ++it)
            if (*it == want) {
                pending.erase(it);
                return true;
            }
        for (;;) {
            const int w = next_word(timeout);
            if (w < 0) return false;
            if (w == want) return true;
            pending.push_back(static_cast<std::uint8_t>(w));
        }
    }
    void put_chunk(unsigned p, const std::string& chunk) {
        for (std::size_t i = 0; i < chunk.size(); ++i)
            wr(static_cast<std::uint16_t>(data_addr(p) + i), std::uint8_t(chunk[i]));
        wr(pflag_addr(p), pflag_ext_use);
        post_word(word(kind_chunk, p));
    }
    std::string receive_frame(unsigned p) {
        std::string bytes;
        for (;;) {
            if (!expect_word(word(kind_chunk, p), ms(20))) return bytes + "<timeout>";
            bool last = false;
            for (unsigned i = 0; i < chunk_size && !last; ++i) {
                const std::uint8_t b = rd(static_cast<std::uint16_t>(data_addr(p) + i));
                bytes += char(b);
                last = b == proto::ETX;
            }
            if (last) wr(pflag_addr(p), pflag_free);
            post_word(word(kind_ack, p));
            if (last) return bytes;
        }
    }
};

} // namespace

TEST(MainCpuWithIdt7130, FramesCrossBothWaysAndBusyStretchesTheMainCpu) {
    MainCpuConfig cfg;
    Idt7130 ram("ram");
    MainCpu cpu("cpu", cfg);
    LeftCpu comm("comm");
    IrqLine int_l("int_l"), int_r("int_r");
    ram.int_l(int_l);
    ram.int_r(int_r);
    comm.int_l(int_l);
    cpu.int_r(int_r);
    comm.bus.bind(ram.left);
    cpu.dpram.bind(ram.right);
    ram.ports[Idt7130::right_port].clock = Clock(cfg.bus_clock_hz).period();
    ram.ports[Idt7130::right_port].cycle_clocks = cfg.access_cycles;

    const std::string a = proto::encode({"EC", 0, std::string(700, 'a')}); // 3 chunks
    const std::string b = proto::encode({"PW", 0, "7,123"});
    std::string got_a, got_b;
    comm.script = [&](LeftCpu& c) {
        // Port 1's word follows port 0's at once: the second post polls int2rbt back to back
        // while the main CPU reads and clears it, so those accesses collide.
        c.put_chunk(0, a.substr(0, chunk_size));
        c.put_chunk(1, b);
        ASSERT_TRUE(c.expect_word(word(kind_ack, 0), ms(5)));
        ASSERT_TRUE(c.expect_word(word(kind_ack, 1), ms(5)));
        c.put_chunk(0, a.substr(chunk_size, chunk_size));
        ASSERT_TRUE(c.expect_word(word(kind_ack, 0), ms(5)));
        c.put_chunk(0, a.substr(2 * chunk_size));
        ASSERT_TRUE(c.expect_word(word(kind_ack, 0), ms(5)));
        got_a = c.receive_frame(0);
        got_b = c.receive_frame(1);
    };
    sc_core::sc_start(ms(40));

    EXPECT_EQ(got_a, a);
    EXPECT_EQ(got_b, proto::encode({"PW", 0, ""}));
    ASSERT_EQ(cpu.received().size(), 2u);
    EXPECT_EQ(cpu.dispatcher().parameters().at(7), 123);
    EXPECT_EQ(ram.peek(pflag_addr(0)), pflag_free);
    EXPECT_EQ(ram.peek(pflag_addr(1)), pflag_free);
    EXPECT_EQ(cpu.mailbox_overwrites(), 0u);
    // BUSY happened on the right port and the main CPU waited exactly what the arbiter reported.
    const auto& right = ram.stats(Idt7130::right_port);
    EXPECT_GT(right.busy, 0u);
    EXPECT_GT(right.wait_states, 0u);
    EXPECT_EQ(cpu.busy_wait(), right.busy_wait);
    EXPECT_EQ(cpu.dpram_accesses(), right.accesses);
}
