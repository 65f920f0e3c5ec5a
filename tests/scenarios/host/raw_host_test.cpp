// Tests of the raw host: timed byte strings with escapes out, every received byte recorded.
#include "scenarios/host/raw_host.h"

#include "models/clock.h"
#include "models/plumbing/config_error.h"
#include "tests/support/sc_test.h"
#include "tests/support/serial_times.h"
#include "tests/support/files.h"

#include <cstdio>
#include <fstream>
#include <sstream>

using namespace rcsim;
using sc_core::sc_time;

TEST(RawHost, SendsAtTheGivenTimesAndRecordsBothWays) {
    const std::string rec_a = (test::scratch_dir() / "raw_a.bin").string();
    const std::string rec_b = (test::scratch_dir() / "raw_b.bin").string();
    const std::string log_b = (test::scratch_dir() / "raw_b.log").string();
    RawHostConfig ca, cb;
    ca.add(us(2000), "\\x05hi\\ACK");
    ca.add(us(100), "A");
    ca.record_path = rec_a;
    cb.add(us(5000), "ok\\r\\n");
    cb.record_path = rec_b;
    cb.log_path = log_b;
    SerialLine line("line");
    RawHost a("a", ca), b("b", cb);
    a.connect(line, SerialLine::a);
    b.connect(line, SerialLine::b);
    sc_core::sc_start();
    const sc_time k_char = test::char_time_9600_8e1();
    ASSERT_EQ(b.received().size(), 5u);
    EXPECT_EQ(b.text(), "A\x05hi\x06");
    EXPECT_EQ(b.received()[0].at, us(100) + k_char);
    EXPECT_EQ(b.received()[1].at, us(2000) + k_char);
    EXPECT_EQ(b.received()[4].at, us(2000) + k_char * 4.0);
    EXPECT_EQ(a.text(), "ok\r\n");
    EXPECT_EQ(a.bytes_sent(), 5u);
    EXPECT_EQ(test::slurp(rec_b), "A\x05hi\x06");
    EXPECT_EQ(test::slurp(rec_a), "ok\r\n");
    std::ifstream fl(log_b);
    std::string first;
    std::getline(fl, first);
    EXPECT_EQ(first, std::to_string((us(100) + k_char).value()) + " 41 ");
}

TEST(RawHost, RecordsLineErrorsAndBreaks) {
    const std::string log_b = (test::scratch_dir() / "raw_err.log").string();
    RawHostConfig ca, cb;
    ca.add(us(0), "xy");
    cb.log_path = log_b;
    SerialLine line("line");
    RawHost a("a", ca), b("b", cb);
    a.connect(line, SerialLine::a);
    b.connect(line, SerialLine::b);
    line.inject(SerialLine::a, 0, FaultKind::flip_data_bit, 1);
    line.inject(SerialLine::a, 1, FaultKind::corrupt_stop);
    test::spawn_checked([&] {
        sc_core::wait(us(10000));
        line.insert_break(SerialLine::a, us(5000));
    }, "break_at_10ms");
    sc_core::sc_start();
    ASSERT_EQ(b.received().size(), 2u);
    EXPECT_TRUE(b.received()[0].parity_error);
    EXPECT_TRUE(b.received()[1].framing_error);
    ASSERT_EQ(b.breaks().size(), 2u);
    std::ifstream fl(log_b);
    std::string l1, l2, l3;
    std::getline(fl, l1);
    std::getline(fl, l2);
    std::getline(fl, l3);
    EXPECT_NE(l1.find(" 7A P"), std::string::npos); // 'x' with bit 1 flipped
    EXPECT_NE(l2.find(" 79 F"), std::string::npos);
    EXPECT_NE(l3.find("BREAK on"), std::string::npos);
}

TEST(RawHost, BadInputIsNamed) {
    RawHostConfig c;
    try {
        c.add(us(0), "ok\\xG0");
        FAIL() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("'\\xG0' at offset 2"), std::string::npos);
    }
    c.record_path = "/nonexistent-dir/rec.bin";
    try {
        RawHost h("h", c);
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/rec.bin"), std::string::npos);
    }
}
