// `rcsim demo`: the timeline shows the round robin, the mailbox exchange and the BUSY collision,
// in that order and at the times the chip models and the scripted 8086 timings give.
#include "tests/support/sc_test.h"

#include <sstream>
#include <string>
#include <vector>

namespace rcsim {
int run_demo(std::ostream& out);
}

TEST(Demo, TimelineShowsRoundRobinMailboxAndBusy) {
    std::ostringstream out;
    EXPECT_EQ(rcsim::run_demo(out), 0);
    const std::string text = out.str();
    const std::vector<std::string> in_order = {
        "8259A initialised",
        " 20.500 us  IR3 requested by DP-RAM INT_L",
        " 20.750 us  INTA #1: IR0 in service, ISR 0x01, IRR 0x0E",
        " 21.500 us  INTA #2: vector 0x20",
        "INTA #2: vector 0x21",
        " 60.000 us  IR0 requested by 82510 #0", // mid-round, while IR1 is served
        "INTA #2: vector 0x22",
        "INTA #2: vector 0x23",
        "comm CPU: read int2ext = 0x10, data[0][0] = 0x01",
        "IR3 withdrawn by DP-RAM INT_L",
        "INT_R asserted",
        "main CPU: reads int2rbt = 0x20",
        "INT_R released",
        "INTA #2: vector 0x20",
        "250.100 us  BUSY_R on 0x153: low at 250.130 us, high at 250.530 us -> 1 wait state(s) for the right port's write",
        "service order: IR0 IR1 IR2 IR3 IR0\n",
        "spurious=0",
        "collisions=1, BUSY wait left=0 right=1 clock(s), pflag[0] = 0x02",
    };
    std::size_t pos = 0;
    for (const auto& line : in_order) {
        const std::size_t found = text.find(line, pos);
        ASSERT_NE(found, std::string::npos) << "missing (or out of order): \"" << line << "\"\n" << text;
        pos = found + line.size();
    }
}
