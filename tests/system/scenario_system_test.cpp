// End to end: the shipped three-port scenario through the scenario runner (the same code path as
// `rcsim run scenarios/three_ports_9600.yaml`): three protocol hosts saturating their ports with
// EC and ST commands for 2 s of simulated time, the real firmware ROM, the main CPU.
#include "scenarios/run/runner.h"
#include "tests/support/sc_test.h"

#include <string>

using namespace rcsim;

TEST(SystemScenario, ThreePortsSaturatedFor2sDeliverEveryFrameExactlyOnce) {
    nlohmann::json report;
    RunOptions opt;
    opt.reproducible = true;
    const int rc = run_scenario(load_scenario(RCSIM_SOURCE_DIR "/scenarios/three_ports_9600.yaml"), opt, report);
    const std::string dump = report.dump(1);
    EXPECT_EQ(rc, 0) << dump;
    EXPECT_EQ(report["passed"], true) << dump;
    EXPECT_GE(report["sim_time_s"].get<double>(), 2.0);
    ASSERT_EQ(report["ports"].size(), 3u);
    std::uint64_t sent = 0;
    for (unsigned p = 0; p < 3; ++p) {
        const auto& port = report["ports"][p];
        SCOPED_TRACE("port " + std::to_string(p));
        EXPECT_EQ(port["overruns"].get<std::uint64_t>(), 0u);
        EXPECT_GT(port["frames_delivered"].get<std::uint64_t>(), 0u);
        EXPECT_EQ(port["frames_failed"].get<std::uint64_t>(), 0u);
        EXPECT_EQ(port["parity_errors"].get<std::uint64_t>(), 0u);
        EXPECT_EQ(port["framing_errors"].get<std::uint64_t>(), 0u);
        sent += port["frames_sent"].get<std::uint64_t>();
    }
    EXPECT_GT(sent, 0u);
    // The interrupt probe measured the run (from bus cycles): every source was seen.
    for (const char* src : {"rs232_0", "rs232_1", "rs232_2", "dpram", "rs232_rx"}) {
        SCOPED_TRACE(src);
        EXPECT_GT(report["interrupts"][src]["count"].get<std::uint64_t>(), 0u);
        EXPECT_GT(report["interrupts"][src]["service_us"]["min"].get<double>(), 0.0);
    }
    // No receive interrupt waited longer than the 4-byte RX FIFO can hold characters (4 character
    // times at 9600 8E1): otherwise a character would have been lost (or the probe paired an
    // interrupt with the wrong IR rise).
    EXPECT_LT(report["interrupts"]["rs232_rx"]["latency_us"]["max"].get<double>(), 4 * 1145.83);
    EXPECT_GT(report["table3"]["rs232_isr_us"].get<double>(), 0.0);
    EXPECT_GT(report["table3"]["dpram_byte_us"].get<double>(), 0.0);
    unsigned found = 0;
    for (const auto& c : report["checks"]) {
        if (c["name"] == "commands_delivered_exactly_once" || c["name"] == "responses_delivered_exactly_once") {
            ++found;
            EXPECT_EQ(c["value"].get<double>(), 0.0) << c.dump();
            EXPECT_EQ(c["passed"], true);
        }
        EXPECT_EQ(c["passed"], true) << c.dump();
    }
    EXPECT_EQ(found, 2u) << "an exactly-once check is missing";
    // The line observers saw every command EOT'd and every response reach its host, once.
    for (unsigned p = 0; p < 3; ++p) {
        SCOPED_TRACE("port " + std::to_string(p));
        const auto& port = report["ports"][p];
        EXPECT_EQ(port["commands"]["host_eot"], port["frames_delivered"]);
        EXPECT_EQ(port["commands"]["main_cpu_received"], port["main_cpu_frames_received"]);
        EXPECT_EQ(port["responses"]["main_cpu_handed"], port["main_cpu_frames_sent"]);
        EXPECT_EQ(port["responses"]["host_received"], port["responses_received"]);
    }
}
