// The report writer on synthetic data: histogram bins, the timeline window, the CSV layout and the
// sections and charts of report.html.
#include "scenarios/report/report_html.h"
#include "scenarios/report/svg.h"
#include "tests/support/printf_fixed.h"
#include "tests/support/sc_test.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <random>
#include <sstream>
#include <string>

using namespace rcsim;
using namespace rcsim::report;

namespace {

std::size_t count_of(const std::string& s, const std::string& what) {
    std::size_t n = 0;
    for (auto at = s.find(what); at != std::string::npos; at = s.find(what, at + what.size())) ++n;
    return n;
}

InterruptRow make_row(unsigned level, double rise, double latency, double service, bool rx = false) {
    InterruptRow r;
    r.level = level;
    r.source = source_name(level);
    r.vector = 8 + level;
    r.has_rise = true;
    r.ir_rise_us = rise;
    r.inta1_us = rise + 1;
    r.inta2_us = rise + 2;
    r.first_isr_us = rise + latency;
    r.has_eoi = true;
    r.eoi_us = r.first_isr_us + service - 5;
    r.iret_done_us = r.first_isr_us + service;
    r.rx = rx;
    return r;
}

nlohmann::json summary(double mn, double mean, double mx, std::size_t n) {
    return {{"count", n}, {"min", mn}, {"mean", mean}, {"p50", mean}, {"p99", mx}, {"max", mx}};
}

nlohmann::json synthetic_report(bool passed) {
    nlohmann::json r;
    r["scenario"] = "synthetic <test>";
    r["seed"] = 3;
    r["rom"] = "comm_fw.rom";
    r["sim_time_s"] = 0.5;
    r["wall_time_s"] = 0.0;
    r["rtf"] = 0.0;
    r["comm_cpu"] = {{"cycles", 4000000}, {"instructions", 500000}, {"clock_hz", 8000000}, {"quantum_us", 10}};
    for (const char* n : {"rs232_0", "rs232_1", "rs232_2", "dpram", "rs232_rx"})
        r["interrupts"][n] = {{"count", 10}, {"latency_us", summary(3, 10, 40, 10)}, {"service_us", summary(20, 80, 150, 10)}};
    r["table3"] = {{"rs232_isr_us", 95.2}, {"rs232_isr_max_us", 150.0}, {"dpram_byte_us", 40.1},
                   {"dpram_bytes_measured", 1234}, {"paper_rs232_isr_us", 82.0}, {"paper_dpram_byte_us", 52.553},
                   {"budget_us", 382.0}, {"margin_us", 382.0 - 95.2 - 40.1}};
    for (int p = 0; p < 3; ++p)
        r["ports"].push_back({{"host", "protocol"}, {"frames_sent", 12}, {"frames_delivered", 12}, {"frames_failed", 0},
                              {"naks", 1}, {"retries", 1}, {"timeouts", 0}, {"overruns", p == 2 ? 1 : 0},
                              {"parity_errors", 0}, {"framing_errors", 0}, {"break_detects", 0},
                              {"rx_fifo_high_water", 2}, {"chars_received", 400}, {"chars_sent", 300},
                              {"char_latency_us", summary(5, 60, 900, 400)}});
    r["main_cpu"] = {{"cycle_jitter_us", summary(0, 3.5, 12, 500)}, {"irq_latency_us", summary(5, 5, 5, 40)},
                     {"control_cycles", 500}, {"cycle_overruns", 0}};
    r["dpram"] = {{"collisions", 0}};
    r["checks"] = nlohmann::json::array();
    r["checks"].push_back({{"name", "overruns"}, {"passed", passed}, {"value", passed ? 0 : 1}, {"limit", 0}});
    r["checks"].push_back({{"name", "table3_margin_us"}, {"passed", true}, {"value", 246.7}, {"limit", 0}});
    r["passed"] = passed;
    return r;
}

std::vector<InterruptRow> synthetic_rows() {
    std::vector<InterruptRow> rows;
    // A steady background every 2 ms and a dense cluster at 50..52 ms.
    for (int i = 0; i < 100; ++i) rows.push_back(make_row(static_cast<unsigned>(i % 4), 2000.0 * i, 5 + i % 7, 60 + i % 30, i % 2 == 0));
    for (int i = 0; i < 30; ++i) rows.push_back(make_row(static_cast<unsigned>(i % 3), 50000.0 + 60.0 * i, 4, 50, true));
    rows.back().depth = 1;
    sort_rows(rows);
    return rows;
}

} // namespace

TEST(ReportHistogram, BinCountsSumToTheSampleCountAndHoldMinAndMax) {
    std::mt19937_64 rng(42);
    std::vector<std::vector<double>> sets = {{}, {7.5}, {3, 3, 3, 3}, {-2.5, 0, 2.5}, {0.001, 0.002, 1000}};
    std::vector<double> big;
    std::lognormal_distribution<double> d(3, 1);
    for (int i = 0; i < 10000; ++i) big.push_back(d(rng));
    sets.push_back(big);
    for (const auto& v : sets) {
        const Histogram h = make_histogram(v, 30);
        EXPECT_EQ(h.total(), v.size());
        if (v.empty()) continue;
        const auto [mn, mx] = std::minmax_element(v.begin(), v.end());
        EXPECT_LE(h.lo, *mn);
        EXPECT_GT(h.hi(), *mx);
        EXPECT_LE(h.counts.size(), 62u); // nice widths: at most about 2 x target bins
        EXPECT_GT(h.counts.front(), 0u);
        EXPECT_GT(h.counts.back(), 0u);
    }
}

TEST(ReportTimeline, BusiestWindowIsTheDensestAndTheEarliestOnATie) {
    const auto rows = synthetic_rows();
    const TimeWindow w = busiest_window(rows, 20000);
    // The cluster starts at 50 ms; a window starting at the background interrupt at 34 ms (or
    // earlier, while it still reaches 50 ms) holds the cluster plus background: the earliest one wins.
    EXPECT_GE(w.interrupts, 30u);
    EXPECT_LE(w.start_us, 50000.0);
    EXPECT_GT(w.end_us, 50000.0 + 60 * 29);
    EXPECT_DOUBLE_EQ(w.end_us - w.start_us, 20000.0);
    // Recount by brute force: no window starting at any interrupt holds more.
    for (const auto& r : rows) {
        std::size_t n = 0;
        for (const auto& q : rows) n += q.start_us() >= r.start_us() && q.start_us() < r.start_us() + 20000;
        EXPECT_LE(n, w.interrupts);
        if (n == w.interrupts) {
            EXPECT_GE(r.start_us(), w.start_us); // earliest on a tie
        }
    }
    // Equal density everywhere: the first interrupt.
    std::vector<InterruptRow> even;
    for (int i = 0; i < 50; ++i) even.push_back(make_row(0, 1000.0 * i, 5, 50));
    EXPECT_DOUBLE_EQ(busiest_window(even, 5000).start_us, 0.0);
    EXPECT_EQ(busiest_window({}, 5000).interrupts, 0u);
}

TEST(ReportCsv, OneLinePerRowWithHeaderAndEmptyFieldsForMissingEvents) {
    auto rows = synthetic_rows();
    rows[3].has_rise = false;
    rows[4].has_eoi = false;
    std::ostringstream os;
    write_interrupts_csv(rows, os);
    std::istringstream in(os.str());
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line,
              "source,level,vector,ir_rise_us,inta1_us,inta2_us,first_isr_us,eoi_us,iret_done_us,latency_us,"
              "service_us,depth,rx,dpram_read_bytes,dpram_write_bytes,handler");
    std::size_t n = 0;
    while (std::getline(in, line)) {
        EXPECT_EQ(count_of(line, ","), 15u) << line;
        if (n == 3) {
            EXPECT_NE(line.find(",,"), std::string::npos) << "no rise: empty ir_rise and latency: " << line;
        }
        ++n;
    }
    EXPECT_EQ(n, rows.size());
}

// The CSV's numbers are those of the documented printf formats: "%.6f" for every time and
// difference in microseconds, "%05X" for the handler. Rows with times made as the probe makes
// them (whole picoseconds / 1e6), from 0 to beyond 2^31 us (where the writer's integer path
// ends), with and without a rise and an EOI, against a writer built on snprintf.
TEST(ReportCsv, NumbersAreThoseOfPrintf) {
    const auto f6 = [](double v) { return rcsim::test::printf_fixed(v, 6); };
    const auto reference = [&f6](const InterruptRow& r) {
        char handler[16];
        std::snprintf(handler, sizeof handler, "%05X", static_cast<unsigned>(r.handler));
        std::ostringstream os;
        os << r.source << ',' << r.level << ',' << r.vector << ',' << (r.has_rise ? f6(r.ir_rise_us) : "") << ','
           << f6(r.inta1_us) << ',' << f6(r.inta2_us) << ',' << f6(r.first_isr_us) << ','
           << (r.has_eoi ? f6(r.eoi_us) : "") << ',' << f6(r.iret_done_us) << ','
           << (r.has_rise ? f6(r.latency_us()) : "") << ',' << f6(r.service_us()) << ',' << r.depth << ','
           << (r.rx ? 1 : 0) << ',' << r.dpram_reads << ',' << r.dpram_writes << ',' << handler << '\n';
        return os.str();
    };
    std::mt19937_64 rng(61131);
    const unsigned long long spans[] = {1'000'000ull, 20'000'000'000'000ull, 2'147'483'648'000'000ull,
                                        4'000'000'000'000'000ull};
    for (int i = 0; i < 40000; ++i) {
        const unsigned long long span = spans[i % 4];
        const unsigned long long t0 = rng() % span;
        const auto us = [](unsigned long long ps) { return static_cast<double>(ps) / 1e6; };
        InterruptRow r;
        r.level = static_cast<unsigned>(rng() % 8);
        r.source = source_name(r.level);
        r.vector = 0x20 + r.level;
        r.has_rise = rng() % 4 != 0;
        r.has_eoi = rng() % 4 != 0;
        r.ir_rise_us = r.has_rise ? us(t0) : 0;
        r.inta1_us = us(t0 + rng() % 5'000'000);
        r.inta2_us = us(t0 + 5'000'000 + rng() % 1000);
        r.first_isr_us = us(t0 + 6'000'000 + rng() % 1'000'000'000);
        r.eoi_us = r.has_eoi ? us(t0 + 1'006'000'000 + rng() % 1000) : 0;
        r.iret_done_us = us(t0 + 1'007'000'000 + rng() % 1000);
        r.depth = static_cast<unsigned>(rng() % 3);
        r.rx = rng() % 2;
        r.dpram_reads = rng() % 400;
        r.dpram_writes = rng() % 400;
        r.handler = static_cast<std::uint32_t>(rng() % 0x100000);
        if (i % 1000 == 0) r.handler = i % 2000 ? 0 : 0x123456; // zero-padded; wider than five digits
        std::ostringstream os;
        write_csv_row(r, os);
        ASSERT_EQ(os.str(), reference(r)) << "row " << i;
    }
}

TEST(ReportHtml, HasEverySectionAndAnSvgPerChart) {
    const auto rows = synthetic_rows();
    HtmlOptions opt;
    opt.trajectory_svg = "<?xml version=\"1.0\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\"><circle r=\"3\"/></svg>\n";
    const std::string html = render_html(synthetic_report(false), rows, opt);
    for (const char* id : {"header", "checks", "table3", "interrupts", "timeline", "ports", "main-cpu", "motion"})
        EXPECT_NE(html.find(std::string(" id=\"") + id + "\""), std::string::npos) << "section " << id << " missing";
    // Table 3, 5 sources x (latency, service), two timelines, character latency, the trajectory.
    EXPECT_EQ(count_of(html, "<svg "), 1u + 10u + 2u + 1u + 1u);
    EXPECT_EQ(count_of(html, "</svg>"), count_of(html, "<svg "));
    EXPECT_NE(html.find("FAILED"), std::string::npos);
    EXPECT_NE(html.find("synthetic &lt;test&gt;"), std::string::npos) << "names are escaped";
    EXPECT_EQ(html.find("<?xml"), std::string::npos) << "the embedded SVG keeps no XML prolog";
    EXPECT_NE(html.find("82.000"), std::string::npos);
    EXPECT_NE(html.find("52.553"), std::string::npos);
    EXPECT_NE(html.find("budget 382.0 us"), std::string::npos);
    // Self-contained: no script, no external resource.
    EXPECT_EQ(html.find("<script"), std::string::npos);
    EXPECT_EQ(html.find("src="), std::string::npos);
    EXPECT_EQ(html.find("href=\"http"), std::string::npos);
    EXPECT_EQ(html.find("url("), std::string::npos);
    // Every chart has axis titles with units.
    EXPECT_EQ(count_of(html, "latency: IR rise to first ISR instruction [us]"), 5u);
    EXPECT_EQ(count_of(html, "service: first ISR instruction to IRET done [us]"), 5u);
    EXPECT_NE(html.find("simulation time [ms]"), std::string::npos);
    EXPECT_NE(html.find("time per received character [us]"), std::string::npos);
    // Deterministic.
    EXPECT_EQ(html, render_html(synthetic_report(false), rows, opt));
    // Without a trajectory there is no motion section.
    const std::string pass = render_html(synthetic_report(true), rows);
    EXPECT_EQ(pass.find("id=\"motion\""), std::string::npos);
    EXPECT_NE(pass.find("PASSED"), std::string::npos);
}

TEST(ReportHtml, EmptyRunStillRenders) {
    nlohmann::json r = synthetic_report(true);
    const std::string html = render_html(r, std::vector<InterruptRow>{});
    EXPECT_NE(html.find("No interrupt completed"), std::string::npos);
    EXPECT_NE(html.find("no samples"), std::string::npos);
}

TEST(ReportHtml, FramesBothWaysShowEveryHostKindWithLossesMarked) {
    nlohmann::json r = synthetic_report(false);
    r["ports"][1]["host"] = "raw";
    r["ports"][1]["commands"] = {{"host_eot", 5}, {"main_cpu_received", 3}, {"lost", 2}};
    r["ports"][1]["responses"] = {{"main_cpu_handed", 4}, {"host_received", 3},
                                  {"dropped", {{"gave_up", 1}, {"port_reset", 0}}}};
    const std::string html = render_html(r, synthetic_rows());
    const auto table = html.find("Frames both ways");
    ASSERT_NE(table, std::string::npos);
    const auto row = html.find("<td class=\"l\">raw</td>", table);
    ASSERT_NE(row, std::string::npos) << "the raw port has its row";
    EXPECT_EQ(html.compare(row, 146,
                           "<td class=\"l\">raw</td><td>5</td><td>3</td><td class=\"bad\">2</td><td>0</td><td>0</td>"
                           "<td>0</td><td>4</td><td>3</td><td>0</td><td class=\"bad\">1</td>"),
              0)
        << html.substr(row, 200);
}

TEST(ReportHtml, AnInterruptedRunSaysSoAndWhereItStopped) {
    nlohmann::json r = synthetic_report(true);
    EXPECT_EQ(render_html(r, synthetic_rows()).find("id=\"interrupted\""), std::string::npos);
    r["interrupted"] = true;
    r["sim_time_s"] = 1.25;
    const std::string html = render_html(r, synthetic_rows());
    EXPECT_NE(html.find("id=\"interrupted\">INTERRUPTED at 1.250000 s simulated"), std::string::npos);
}

TEST(ReportSvg, NumbersAreFixedAndTextIsEscaped) {
    EXPECT_EQ(svg::num(-0.0001, 2), "0.00");
    EXPECT_EQ(svg::num(1.005, 1), "1.0");
    EXPECT_EQ(svg::num(12.4, 0), "12");
    EXPECT_EQ(svg::esc("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    EXPECT_DOUBLE_EQ(svg::nice_step(100, 10), 10);
    EXPECT_DOUBLE_EQ(svg::nice_step(7, 10), 1);
    EXPECT_DOUBLE_EQ(svg::nice_step(0.3, 4), 0.1);
    const auto t = svg::nice_ticks(0, 382, 5);
    ASSERT_FALSE(t.empty());
    EXPECT_DOUBLE_EQ(t.front(), 0);
    EXPECT_DOUBLE_EQ(t.back(), 300);
}

namespace {

// A long random run in entry order: depth-0 interrupts one after another, some with a nested one
// inside (entered later, returning first), IR rises up to 1.5 ms before their INTA (so starts
// are out of entry order), a few without a rise.
std::vector<InterruptRow> random_run(std::uint64_t seed, int n) {
    std::mt19937_64 rng(seed);
    std::vector<InterruptRow> rows;
    double t = 100;
    for (int i = 0; i < n; ++i) {
        t += 20 + static_cast<double>(rng() % 3000) / 4;
        InterruptRow r = make_row(static_cast<unsigned>(rng() % 4), 0, 0, 0);
        r.inta1_us = t;
        r.inta2_us = t + 1;
        r.first_isr_us = t + 5;
        r.has_rise = rng() % 10 != 0;
        r.ir_rise_us = r.has_rise ? t - static_cast<double>(rng() % 6000) / 4 : 0;
        r.iret_done_us = r.first_isr_us + 30 + static_cast<double>(rng() % 800) / 4;
        rows.push_back(r);
        if (rng() % 5 == 0) { // a nested interrupt inside this one
            InterruptRow q = r;
            q.level = 3;
            q.source = source_name(3);
            q.depth = 1;
            q.inta1_us = r.first_isr_us + 10;
            q.inta2_us = q.inta1_us + 1;
            q.first_isr_us = q.inta1_us + 5;
            q.ir_rise_us = q.inta1_us - 2;
            q.iret_done_us = r.iret_done_us - 3;
            rows.push_back(q);
        }
        t = r.iret_done_us;
    }
    return rows;
}

std::vector<TimelineRow> drawn_in(const std::vector<InterruptRow>& rows, double t0, double t1) {
    std::vector<TimelineRow> out;
    double open_until = -1;
    for (const auto& r : rows) {
        const bool nested = open_until > r.iret_done_us;
        open_until = std::max(open_until, r.iret_done_us);
        if (!(r.iret_done_us < t0 || r.start_us() > t1)) out.push_back({r, nested});
    }
    return out;
}

void expect_same(const std::vector<TimelineRow>& got, const std::vector<TimelineRow>& want) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].row.inta1_us, want[i].row.inta1_us) << i;
        EXPECT_EQ(got[i].nested, want[i].nested) << i;
    }
}

} // namespace

TEST(ReportTimeline, OnlineWindowsAreThoseOfTheWholeRowList) {
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        const auto rows = random_run(seed, 3000);
        // Settled after each row with the earliest start still to come, as the probe does.
        std::vector<double> later_start(rows.size() + 1, std::numeric_limits<double>::infinity());
        for (std::size_t i = rows.size(); i-- > 0;) later_start[i] = std::min(later_start[i + 1], rows[i].start_us());
        TimelineWindows tl(5000, 1000);
        std::size_t most_held = 0;
        for (std::size_t i = 0; i < rows.size(); ++i) {
            tl.add(rows[i]);
            if (i % 3 == 0) tl.settled(later_start[i + 1]);
            most_held = std::max(most_held, tl.held());
        }
        tl.finish();
        EXPECT_EQ(tl.rows(), rows.size());
        const TimeWindow w = busiest_window(rows, 5000);
        EXPECT_EQ(tl.busiest().start_us, w.start_us);
        EXPECT_EQ(tl.busiest().interrupts, w.interrupts);
        expect_same(tl.busiest_rows(), drawn_in(rows, w.start_us, w.end_us));
        // The zoom: the first row of the longest latency.
        const InterruptRow* worst = nullptr;
        for (const auto& r : rows)
            if (r.has_rise && (!worst || r.latency_us() > worst->latency_us())) worst = &r;
        ASSERT_NE(worst, nullptr);
        EXPECT_EQ(tl.worst().inta1_us, worst->inta1_us);
        EXPECT_GE(tl.zoom_start_us(), worst->start_us() - 0.3 * tl.zoom_width_us());
        EXPECT_LE(tl.zoom_start_us(), worst->start_us());
        expect_same(tl.zoom_rows(), drawn_in(rows, tl.zoom_start_us(), tl.zoom_start_us() + tl.zoom_width_us()));
        // Held: the rows of a few windows, not the run (3000 rows over about 2.5 s).
        EXPECT_LT(most_held, 300u);
    }
}

TEST(ReportLog, StreamsTheCsvOfTheRowsAndKeepsTheirHistograms) {
    const auto rows = synthetic_rows();
    std::ostringstream streamed, whole;
    InterruptLog log;
    log.write_csv_to(&streamed);
    for (const auto& r : rows) log.add(r);
    log.finish();
    write_interrupts_csv(rows, whole);
    EXPECT_EQ(streamed.str(), whole.str());
    EXPECT_EQ(log.rows(), rows.size());
    std::size_t level0 = 0, rx = 0;
    for (const auto& r : rows) {
        level0 += r.level == 0;
        rx += r.rx;
    }
    EXPECT_EQ(log.service(0).count(), level0);
    EXPECT_EQ(log.service(4).count(), rx) << "histogram 4 is rs232_rx";
    // A histogram of a sample set bins like one of the samples themselves.
    std::vector<double> svc;
    for (const auto& r : rows)
        if (r.level == 0) svc.push_back(r.service_us());
    EXPECT_EQ(make_histogram(log.service(0)).counts, make_histogram(svc).counts);
}

TEST(ReportTimeline, TheZoomReachesBackToALongInterruptThatEndedBeforeIt) {
    // L runs 6 ms (longer than the 5 ms window); when M's start is in, no busiest window needs L
    // any more. The longest latency comes after them, with a service of 9.9 ms: its zoom
    // (case "entry and service": width 9.9 / 0.6 = 16.5 ms, from 0.3 of it before its INTA,
    // 10.8 - 4.95 = 5.85 ms) still shows the end of L at 6 ms.
    auto row = [](double rise, double inta1, double iret) {
        InterruptRow r = make_row(0, rise, inta1 + 5 - rise, iret - inta1 - 5);
        r.inta1_us = inta1;
        r.inta2_us = inta1 + 1;
        return r;
    };
    const InterruptRow l = row(0, 100, 6000), m = row(10600, 10600, 10620), w = row(10650, 10800, 20700);
    TimelineWindows tl(5000, 1000);
    tl.add(l);
    tl.add(m);
    tl.settled(10650); // the probe's horizon: w's IR rise is pending
    tl.add(w);
    tl.finish();
    ASSERT_EQ(tl.worst().inta1_us, w.inta1_us);
    EXPECT_NEAR(tl.zoom_start_us(), 5850, 1e-6);
    ASSERT_EQ(tl.zoom_rows().size(), 3u) << "L, M and the zoomed interrupt";
    EXPECT_EQ(tl.zoom_rows()[0].row.inta1_us, l.inta1_us);
}
