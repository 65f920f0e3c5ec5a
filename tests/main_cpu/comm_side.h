// Test doubles for the main CPU: a fake IDT7130 (1 KB, mailbox interrupts, configurable BUSY wait
// states on the right port, an access log) and a scripted comm CPU that drives its left port the
// way the firmware does: chunks, pflag, mailbox words.
#pragma once

#include "models/dpram_layout.h"
#include "models/frame_codec.h"
#include "models/bus.h"
#include "tests/support/sc_test.h"

#include <gtest/gtest.h>
#include <systemc>
#include <tlm>
#include <tlm_utils/simple_target_socket.h>

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

namespace rcsim::test {

using Line = sc_core::sc_signal<bool, sc_core::SC_MANY_WRITERS>;

struct RightAccess {
    sc_core::sc_time time;
    BusCycle kind;
    std::uint16_t addr;
    std::uint8_t value;
    int initiator;
    unsigned wait_states;
};

/// 1 KB with the IDT7130 mailbox rules. The left side is a plain function API (the scripted comm
/// CPU calls it from its thread); the right side is the TLM target the main CPU drives.
class FakeDpram : public sc_core::sc_module {
public:
    tlm_utils::simple_target_socket<FakeDpram> right;
    Line int_r{"int_r_line"};
    Line int_l{"int_l_line"};
    std::array<std::uint8_t, 1024> mem{};
    std::vector<RightAccess> log;
    unsigned busy_wait_states = 0; // answered to every right-port access

    explicit FakeDpram(sc_core::sc_module_name n) : sc_module(n), right("right") {
        right.register_b_transport(this, &FakeDpram::b_transport);
    }

    void left_write(std::uint16_t addr, std::uint8_t v) {
        mem.at(addr) = v;
        if (addr == dpram_layout::int2rbt) int_r.write(true);
    }
    std::uint8_t left_read(std::uint16_t addr) {
        if (addr == dpram_layout::int2ext) int_l.write(false);
        return mem.at(addr);
    }

    /// Right-port writes to one address, in order.
    std::vector<RightAccess> writes_to(std::uint16_t addr) const {
        std::vector<RightAccess> out;
        for (const auto& a : log)
            if (a.addr == addr && a.kind == BusCycle::mem_write) out.push_back(a);
        return out;
    }

    /// Right-port accesses to one address, in order.
    std::vector<RightAccess> accesses_to(std::uint16_t addr) const {
        std::vector<RightAccess> out;
        for (const auto& a : log)
            if (a.addr == addr) out.push_back(a);
        return out;
    }

private:
    void b_transport(tlm::tlm_generic_payload& gp, sc_core::sc_time&) {
        BusView ext(gp, false);
        const auto addr = static_cast<std::uint16_t>(gp.get_address());
        EXPECT_EQ(gp.get_data_length(), 1u) << "main CPU must make byte accesses";
        EXPECT_EQ(ext->start, sc_core::sc_time_stamp()) << "initiator must sync before the access";
        if (addr >= mem.size()) {
            gp.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
            return;
        }
        std::uint8_t* data = gp.get_data_ptr();
        if (gp.is_write()) {
            mem[addr] = *data;
            if (addr == dpram_layout::int2ext) int_l.write(true);
        } else {
            *data = mem[addr];
            if (addr == dpram_layout::int2rbt) int_r.write(false);
        }
        ext->wait_states = busy_wait_states;
        log.push_back(RightAccess{sc_core::sc_time_stamp(), ext->kind, addr, *data, ext->initiator,
                                  busy_wait_states});
        gp.set_response_status(tlm::TLM_OK_RESPONSE);
    }
};

/// What the comm CPU saw of one frame the main CPU sent it.
struct ReceivedByComm {
    std::string bytes;
    unsigned chunks = 0;
    std::vector<std::uint8_t> pflag_at_chunk; // pflag[p] when each chunk's word arrived
};

/// The comm CPU side, scripted: runs `script` in its own thread. Its helpers may only be called
/// from that script. Chunk copies take no time (the comm CPU's speed is not under test here).
class CommSide : public sc_core::sc_module {
public:
    std::function<void(CommSide&)> script;
    std::vector<std::uint8_t> words; // every int2ext word read, in order
    std::deque<std::uint8_t> pending; // words read while waiting for another
    bool handshake = true; // clear int2ext after reading it; write int2rbt only when it reads 0

    CommSide(sc_core::sc_module_name n, FakeDpram& ram) : sc_module(n), ram_(ram) {
        rcsim::test::spawn_checked([this] { run(); }, "run");
    }

    /// Next int2ext word (from the pending ones first), or -1 when none comes within `timeout`.
    int next_word(const sc_core::sc_time& timeout) {
        if (!pending.empty()) {
            const int w = pending.front();
            pending.pop_front();
            return w;
        }
        if (!ram_.int_l.read()) wait(timeout, ram_.int_l.posedge_event());
        if (!ram_.int_l.read()) return -1;
        const std::uint8_t w = ram_.left_read(dpram_layout::int2ext);
        if (handshake) ram_.left_write(dpram_layout::int2ext, 0); // own mailbox: no interrupt
        words.push_back(w);
        wait(sc_core::SC_ZERO_TIME); // let INT_L fall before anyone looks again
        return w;
    }

    /// Waits for exactly `want`, keeping other words for later. Fails the test on timeout.
    bool expect_word(std::uint8_t want, const sc_core::sc_time& timeout) {
        const sc_core::sc_time deadline = sc_core::sc_time_stamp() + timeout;
        std::deque<std::uint8_t> others;
        for (;;) {
            const sc_core::sc_time left = deadline > sc_core::sc_time_stamp()
                                              ? deadline - sc_core::sc_time_stamp()
                                              : sc_core::SC_ZERO_TIME;
            const int w = next_word(left);
            if (w == want) {
                for (auto o : others) pending.push_back(o);
                return true;
            }
            if (w < 0) {
                ADD_FAILURE() << "no mailbox word 0x" << std::hex << int(want) << " within " << timeout;
                for (auto o : others) pending.push_back(o);
                return false;
            }
            others.push_back(static_cast<std::uint8_t>(w));
        }
    }

    /// Writes a word to int2rbt once the main CPU has taken the previous one. A real firmware
    /// cannot see INT_R; this idealised one does, so that the tests never lose a word by accident.
    /// With the handshake it waits, as a real one could, until the main CPU has cleared int2rbt.
    void post_word(std::uint8_t w) {
        if (handshake)
            while (ram_.mem[dpram_layout::int2rbt] != 0) wait(sc_core::sc_time(1, sc_core::SC_US));
        else
            while (ram_.int_r.read()) wait(ram_.int_r.negedge_event());
        ram_.left_write(dpram_layout::int2rbt, w);
        wait(sc_core::SC_ZERO_TIME);
    }

    /// Writes one chunk into data[p] and announces it with 0x1p.
    void put_chunk(unsigned p, const std::string& chunk) {
        for (std::size_t i = 0; i < chunk.size(); ++i)
            ram_.left_write(static_cast<std::uint16_t>(dpram_layout::data_addr(p) + i), std::uint8_t(chunk[i]));
        ram_.left_write(dpram_layout::pflag_addr(p), dpram_layout::pflag_ext_use);
        post_word(dpram_layout::word(dpram_layout::kind_chunk, p));
    }

    /// Sends a whole frame to the main CPU, chunk by chunk, waiting for each ACK as the firmware does.
    bool send_frame(unsigned p, const std::string& bytes,
                    const sc_core::sc_time& timeout = sc_core::sc_time(10, sc_core::SC_MS)) {
        for (std::size_t off = 0; off < bytes.size(); off += dpram_layout::chunk_size) {
            put_chunk(p, bytes.substr(off, dpram_layout::chunk_size));
            if (!expect_word(dpram_layout::word(dpram_layout::kind_ack, p), timeout)) return false;
        }
        return true;
    }

    /// Receives one frame from the main CPU on port p: per chunk, wait for 0x1p, copy up to ETX,
    /// free pflag after the last chunk (the reader does), then ACK with 0x2p in int2rbt.
    ReceivedByComm receive_frame(unsigned p, const sc_core::sc_time& timeout = sc_core::sc_time(10, sc_core::SC_MS)) {
        ReceivedByComm r;
        for (;;) {
            if (!expect_word(dpram_layout::word(dpram_layout::kind_chunk, p), timeout)) return r;
            r.pflag_at_chunk.push_back(ram_.mem[dpram_layout::pflag_addr(p)]);
            ++r.chunks;
            bool last = false;
            for (unsigned i = 0; i < dpram_layout::chunk_size && !last; ++i) {
                const std::uint8_t b = ram_.mem[dpram_layout::data_addr(p) + i];
                r.bytes += char(b);
                last = b == proto::ETX;
            }
            if (last) ram_.left_write(dpram_layout::pflag_addr(p), dpram_layout::pflag_free);
            post_word(dpram_layout::word(dpram_layout::kind_ack, p));
            if (last) return r;
        }
    }

    FakeDpram& ram() { return ram_; }

private:
    void run() {
        if (script) script(*this);
    }
    FakeDpram& ram_;
};

} // namespace rcsim::test
