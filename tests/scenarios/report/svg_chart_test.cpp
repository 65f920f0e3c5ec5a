// The chart module's drawing calls (scenarios/report/svg.h): each element's exact markup, so that the
// same picture is always the same bytes (numbers with one decimal, text escaped).
#include "scenarios/report/svg.h"
#include "tests/support/printf_fixed.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace rcsim;
using rcsim::test::printf_fixed;

namespace {

/// The body of a 100 x 50 document after `draw` (the <svg> wrapper stripped).
template <typename F> std::string body_of(F draw) {
    svg::Doc d(100, 50);
    draw(d);
    const std::string s = d.str();
    const auto open_end = s.find(">\n") + 2;
    return s.substr(open_end, s.rfind("</svg>") - open_end);
}

TEST(SvgChart, DocumentHeaderNamesSizeAndLabel) {
    svg::Doc d(640, 680, "a & b");
    EXPECT_EQ(d.str(), "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"640\" height=\"680\" viewBox=\"0 0 640 680\" "
                       "font-family=\"sans-serif\" font-size=\"12\" role=\"img\" aria-label=\"a &amp; b\">\n</svg>\n");
}

TEST(SvgChart, PolylineListsItsPointsInOrder) {
    EXPECT_EQ(body_of([](svg::Doc& d) { d.polyline({{1, 2}, {3.26, -0.04}, {10, 20}}, "#123", 2); }),
              "<polyline fill=\"none\" stroke=\"#123\" stroke-width=\"2.0\" points=\"1.0,2.0 3.3,0.0 10.0,20.0\"/>\n");
    EXPECT_EQ(body_of([](svg::Doc& d) { d.polyline({{0, 0}}, "red", 1.5, "stroke-dasharray=\"4 3\""); }),
              "<polyline fill=\"none\" stroke=\"red\" stroke-width=\"1.5\" stroke-dasharray=\"4 3\" points=\"0.0,0.0\"/>\n");
}

TEST(SvgChart, MarkersAreCentredOnTheirPoint) {
    // size 6: circle radius 3; square 6 x 6 from (x-3, y-3); cross from (x-3, y-3) to (x+3, y+3).
    EXPECT_EQ(body_of([](svg::Doc& d) { d.marker(10, 20, svg::Marker::circle, "blue"); }),
              "<circle cx=\"10.0\" cy=\"20.0\" r=\"3.0\" fill=\"blue\"/>\n");
    EXPECT_EQ(body_of([](svg::Doc& d) { d.marker(10, 20, svg::Marker::square, "blue", 4); }),
              "<rect x=\"8.0\" y=\"18.0\" width=\"4.0\" height=\"4.0\" fill=\"blue\"/>\n");
    EXPECT_EQ(body_of([](svg::Doc& d) { d.marker(10, 20, svg::Marker::cross, "red"); }),
              "<line x1=\"7.0\" y1=\"17.0\" x2=\"13.0\" y2=\"23.0\" stroke=\"red\" stroke-width=\"1.5\"/>\n"
              "<line x1=\"7.0\" y1=\"23.0\" x2=\"13.0\" y2=\"17.0\" stroke=\"red\" stroke-width=\"1.5\"/>\n");
}

TEST(SvgChart, TitleIsCentredAndFrameIsUnfilled) {
    EXPECT_EQ(body_of([](svg::Doc& d) { d.title("<run>"); }),
              "<text x=\"50.0\" y=\"30.0\" text-anchor=\"middle\" font-size=\"16.0\">&lt;run&gt;</text>\n");
    EXPECT_EQ(body_of([](svg::Doc& d) { d.frame(5, 6, 70, 30); }),
              "<rect x=\"5.0\" y=\"6.0\" width=\"70.0\" height=\"30.0\" fill=\"none\" stroke=\"#333\"/>\n");
}

TEST(SvgChart, LegendRowsGoDownWithTheirSamples) {
    EXPECT_EQ(body_of([](svg::Doc& d) {
                  d.legend(10, 20, {{"cmd", "#00f"}, {"act", "#f00", "4 3"}, {"bar", "#0f0", "", true}});
              }),
              "<line x1=\"10.0\" y1=\"20.0\" x2=\"40.0\" y2=\"20.0\" stroke=\"#00f\" stroke-width=\"2.0\"/>\n"
              "<text x=\"46.0\" y=\"24.0\">cmd</text>\n"
              "<line x1=\"10.0\" y1=\"38.0\" x2=\"40.0\" y2=\"38.0\" stroke=\"#f00\" stroke-width=\"2.0\" "
              "stroke-dasharray=\"4 3\"/>\n"
              "<text x=\"46.0\" y=\"42.0\">act</text>\n"
              "<rect x=\"18.0\" y=\"49.0\" width=\"14.0\" height=\"14.0\" fill=\"#0f0\"/>\n"
              "<text x=\"46.0\" y=\"60.0\">bar</text>\n");
}

} // namespace

// svg::num's digits are those of printf("%.*f"), the format every report column is documented
// in: the C conversion rounds the exact binary value, ties to even. Exact ties (0.125, 2.5),
// values just off a tie, negative zero, large and tiny numbers, and random picosecond times
// at the interrupts.csv precision of 6 decimals.
TEST(SvgChart, NumberDigitsAreThoseOfPrintfFixed) {
    EXPECT_EQ(svg::num(0.125, 2), "0.12"); // a tie in binary: to even
    EXPECT_EQ(svg::num(0.375, 2), "0.38");
    EXPECT_EQ(svg::num(2.5, 0), "2");
    EXPECT_EQ(svg::num(-0.04, 1), "0.0"); // no negative zero
    EXPECT_EQ(svg::num(1e300, 0).size(), 301u);
    for (double v : {0.0, -0.0, 0.05, 0.15, 0.25, 1.005, 4805.25, 1e-7, 123456789.123456789, -3.75, 1e21, 5e-324})
        for (int d = 0; d <= 9; ++d) EXPECT_EQ(svg::num(v, d), printf_fixed(v, d)) << v << " " << d;
    std::mt19937_64 rng(13);
    for (int i = 0; i < 100000; ++i) {
        const double ps = static_cast<double>(rng() % 20'000'000'000'000ull); // up to 20 s
        const double us = ps / 1e6;
        ASSERT_EQ(svg::num(us, 6), printf_fixed(us, 6)) << us;
        const double any = std::ldexp(static_cast<double>(rng() >> 11), int(rng() % 80) - 60) * (i % 2 ? 1 : -1);
        const int d = static_cast<int>(rng() % 10);
        ASSERT_EQ(svg::num(any, d), printf_fixed(any, d)) << any << " " << d;
    }
}
