// The set-up of the main CPU tests (main_cpu_test.cpp: frames, tokens, ports, mailbox words;
// main_cpu_timing_test.cpp: the control cycle and the one processor's timing): a main CPU wired
// to a fake IDT7130 and a scripted comm CPU (comm_side.h), a motion layer that records, and
// frame helpers.
#pragma once

#include "main_cpu/main_cpu.h"
#include "tests/main_cpu/comm_side.h"
#include "tests/support/sc_test.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rcsim::test::main_cpu {

using namespace rcsim::dpram_layout;
using sc_core::sc_time;

/// Records motion commands and control cycles.
class FakeMotion : public MotionInterface {
public:
    std::vector<std::pair<std::string, std::string>> commands;
    std::vector<sc_time> cycles;
    MotionReply command(const std::string& token, const std::string& data) override {
        commands.emplace_back(token, data);
        return MotionReply{bch::ok, "accepted"};
    }
    void control_cycle(const sc_time& now) override { cycles.push_back(now); }
    std::vector<std::int64_t> positions() const override { return {1, 2}; }
    std::string state() const override { return "STANDSTILL"; }
};

/// One main CPU wired to a fake DP-RAM and a scripted comm CPU.
struct MainCpuOnFakes {
    FakeDpram ram{"ram"};
    MainCpu cpu;
    CommSide comm{"comm", ram};

    explicit MainCpuOnFakes(const MainCpuConfig& c = MainCpuConfig()) : cpu("cpu", c) {
        cpu.dpram.bind(ram.right);
        cpu.int_r(ram.int_r);
    }
    std::uint8_t pflag(unsigned p) const { return ram.mem[pflag_addr(p)]; }
    /// Time of one bus cycle of the main CPU with `ws` wait states and `extra` loop cycles.
    sc_time cycle(unsigned ws = 0, unsigned extra = 0) const {
        return Clock(cpu.config().bus_clock_hz).cycles(cpu.config().access_cycles + ws + extra);
    }
};

inline std::string cmd(const std::string& token, const std::string& data) {
    return proto::encode({token, 0, data});
}

inline proto::Frame decoded(const std::string& bytes) {
    proto::Frame f;
    const std::string why = proto::decode(bytes, f);
    EXPECT_EQ(why, "");
    return f;
}


} // namespace rcsim::test::main_cpu
