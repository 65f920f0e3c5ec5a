// The chart module's drawing calls (scenarios/svg.h): each element's exact markup, so that the
// same picture is always the same bytes (numbers with one decimal, text escaped).
#include "scenarios/svg.h"

#include <gtest/gtest.h>

using namespace rcsim;

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
