// The validator (trace_check.h) on hand-made traces: each rule it enforces has a trace that
// breaks it; and the writer (scenarios/trace/trace_events.h) against the format's rules.
#include "tests/scenarios/trace/trace_check.h"

#include "models/plumbing/config_error.h"
#include "scenarios/trace/trace_events.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using nlohmann::json;
using rcsim::test::check_trace;

namespace {

json doc(const char* events) { return json::parse(std::string("{\"traceEvents\":[") + events + "]}"); }

TEST(TraceCheck, BalancedNestedSlicesInstantsAndCountersPass) {
    const json d = doc(R"({"ph":"B","name":"a","pid":1,"tid":1,"ts":1},
                          {"ph":"B","name":"b","pid":1,"tid":1,"ts":2},
                          {"ph":"i","s":"t","name":"x","pid":1,"tid":1,"ts":2.5},
                          {"ph":"E","name":"b","pid":1,"tid":1,"ts":3},
                          {"ph":"E","pid":1,"tid":1,"ts":4},
                          {"ph":"X","name":"c","pid":1,"tid":2,"ts":0.5,"dur":10},
                          {"ph":"X","name":"d","pid":1,"tid":2,"ts":1,"dur":2},
                          {"ph":"X","name":"e","pid":1,"tid":2,"ts":10.5,"dur":0},
                          {"ph":"C","name":"n","pid":2,"ts":0,"args":{"value":1}},
                          {"ph":"C","name":"n","pid":2,"ts":7,"args":{"value":0}})");
    EXPECT_TRUE(check_trace(d).empty()) << check_trace(d)[0];
}

TEST(TraceCheck, AnUnclosedBeginFails) {
    const auto p = check_trace(doc(R"({"ph":"B","name":"a","pid":1,"tid":1,"ts":1},
                                      {"ph":"B","name":"b","pid":1,"tid":1,"ts":2},
                                      {"ph":"E","pid":1,"tid":1,"ts":3})"));
    ASSERT_EQ(p.size(), 1u);
    EXPECT_NE(p[0].find("never closed"), std::string::npos) << p[0];
}

TEST(TraceCheck, AnEndWithoutBeginOrOfAnotherSliceFails) {
    EXPECT_EQ(check_trace(doc(R"({"ph":"E","pid":1,"tid":1,"ts":3})")).size(), 1u);
    // B on one track, E on another: each track is unbalanced.
    EXPECT_EQ(check_trace(doc(R"({"ph":"B","name":"a","pid":1,"tid":1,"ts":1},
                                 {"ph":"E","pid":1,"tid":2,"ts":2})")).size(), 2u);
    EXPECT_EQ(check_trace(doc(R"({"ph":"B","name":"a","pid":1,"tid":1,"ts":1},
                                 {"ph":"E","name":"z","pid":1,"tid":1,"ts":2})")).size(), 1u);
}

TEST(TraceCheck, TimeGoingBackOnATrackFails) {
    const auto p = check_trace(doc(R"({"ph":"i","s":"t","name":"x","pid":1,"tid":1,"ts":5},
                                      {"ph":"i","s":"t","name":"y","pid":1,"tid":2,"ts":1},
                                      {"ph":"i","s":"t","name":"z","pid":1,"tid":1,"ts":4.999})"));
    ASSERT_EQ(p.size(), 1u) << "other tracks are independent";
    EXPECT_NE(p[0].find("before the track's previous"), std::string::npos) << p[0];
    EXPECT_EQ(check_trace(doc(R"({"ph":"C","name":"n","pid":2,"ts":3,"args":{"value":1}},
                                 {"ph":"C","name":"n","pid":2,"ts":2,"args":{"value":0}})")).size(), 1u);
}

TEST(TraceCheck, OverlappingCompleteSlicesAndBadDurationsFail) {
    EXPECT_EQ(check_trace(doc(R"({"ph":"X","name":"a","pid":1,"tid":1,"ts":1,"dur":5},
                                 {"ph":"X","name":"b","pid":1,"tid":1,"ts":2,"dur":5})")).size(), 1u);
    EXPECT_EQ(check_trace(doc(R"({"ph":"X","name":"a","pid":1,"tid":1,"ts":1,"dur":-1})")).size(), 1u);
    EXPECT_EQ(check_trace(doc(R"({"ph":"X","name":"a","pid":1,"tid":1,"ts":1})")).size(), 1u);
}

TEST(TraceCheck, NotATraceAndEventsWithoutTimeFail) {
    EXPECT_EQ(check_trace(json::parse(R"({"events":[]})")).size(), 1u);
    EXPECT_EQ(check_trace(doc(R"({"ph":"i","name":"x","pid":1,"tid":1})")).size(), 1u);
    EXPECT_EQ(check_trace(doc(R"({"ph":"C","name":"n","pid":2,"ts":1,"args":{"value":"high"}})")).size(), 1u);
    EXPECT_EQ(check_trace(doc(R"({"ph":"Q","name":"n","pid":2,"ts":1})")).size(), 1u);
}

// ---- the writer ----

TEST(TraceEvents, MicrosecondsKeepEveryPicosecond) {
    EXPECT_EQ(rcsim::trace::micros(0), "0.000000");
    EXPECT_EQ(rcsim::trace::micros(125'000), "0.125000");          // one 8 MHz clock
    EXPECT_EQ(rcsim::trace::micros(1'000'001), "1.000001");
    EXPECT_EQ(rcsim::trace::micros(3'600'000'000'000'123ULL), "3600000000.000123"); // an hour, + 123 ps
}

TEST(TraceEvents, NamesAreEscapedJson) {
    EXPECT_EQ(rcsim::trace::quoted("a\"b\\c\n"), "\"a\\\"b\\\\c\\u000a\"");
}

TEST(TraceEvents, TheWrittenFileParsesAndPasses) {
    const std::string path = std::string(RCSIM_TRACE_WORK) + "/writer.json";
    std::filesystem::create_directories(RCSIM_TRACE_WORK);
    rcsim::trace::TraceEventWriter w(path);
    w.process_name(1, "p \"one\"", 0);
    w.thread_name(1, 2, "t", 0);
    w.complete(1, 2, "outer", 1'000'000, 5'000'000, "\"k\":1");
    w.complete(1, 2, "inner", 2'000'000, 125'000);
    w.instant(1, 2, "mark", 2'062'500);
    w.counter(1, "level", 0, 3);
    w.close();
    std::ifstream in(path);
    const json d = json::parse(in);
    EXPECT_TRUE(check_trace(d).empty());
    const auto& ev = rcsim::test::trace_events(d);
    ASSERT_EQ(ev.size(), 8u); // 4 metadata + 4
    EXPECT_DOUBLE_EQ(ev[5]["ts"].get<double>(), 2.0);
    EXPECT_DOUBLE_EQ(ev[5]["dur"].get<double>(), 0.125);
    EXPECT_DOUBLE_EQ(ev[6]["ts"].get<double>(), 2.0625);
    EXPECT_EQ(ev[4]["args"]["k"], 1);
    EXPECT_EQ(ev[7]["args"]["value"], 3);
    EXPECT_EQ(rcsim::test::thread_names(d).at({1, 2}), "t");
}

TEST(TraceEvents, AFullDiskIsAnErrorNamingTheFile) {
    // /dev/full takes the open and fails every write with ENOSPC.
    rcsim::trace::TraceEventWriter w("/dev/full");
    for (int i = 0; i < 10000; ++i) w.counter(1, "n", static_cast<std::uint64_t>(i), i);
    try {
        w.close();
        FAIL() << "close() accepted a failed write";
    } catch (const rcsim::ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("/dev/full: cannot write the trace file"), std::string::npos) << e.what();
    }
}

TEST(TraceEvents, AnUncreatableFileIsAnError) {
    EXPECT_THROW(rcsim::trace::TraceEventWriter("/nonexistent-dir/x.json"), rcsim::ConfigError);
}

} // namespace
