// The report's error plot: round ticks, labels that never overlap, absolute errors on a log
// axis that ends at the render's own time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>

#include "runtime/report/sequence_report.h"
#include "runtime/report/svg_plot.h"

namespace crex {
namespace {

bool is_one_two_five(double step) {
    double m = step / std::pow(10.0, std::floor(std::log10(step) + 1e-12));
    return std::fabs(m - 1) < 1e-9 || std::fabs(m - 2) < 1e-9 || std::fabs(m - 5) < 1e-9;
}

TEST(ErrorPlot, TicksAreRoundStepsFromZeroPastTheEnd) {
    for (double max : {0.0841, 0.168, 1.0, 2.04, 7.3, 31.0, 1234.5}) {
        auto t = nice_ticks(max, 5);
        ASSERT_GE(t.size(), 3u) << max;
        EXPECT_EQ(t.front(), 0.0);
        EXPECT_LE(t.back(), max * (1 + 1e-9)) << max;
        EXPECT_GT(t.back() + (t[1] - t[0]), max) << max;  // the next tick would pass the end
        EXPECT_TRUE(is_one_two_five(t[1] - t[0])) << max << ": step " << t[1] - t[0];
        EXPECT_LE(t.size(), 11u) << max;
    }
    EXPECT_EQ(tick_label(0.2), "0.2");
    EXPECT_EQ(tick_label(1.5), "1.5");
    EXPECT_EQ(tick_label(10), "10");
    EXPECT_EQ(tick_label(0.001), "0.001");
}

TEST(ErrorPlot, StageLabelsCloserThanAGapShareOne) {
    auto l = stage_labels({{100, "preview"}, {105, "guidance"}, {200, "selective"}, {212, "guidance"}, {226, "selective"}}, 13);
    ASSERT_EQ(l.size(), 3u);
    EXPECT_EQ(l[0].text, "preview / guidance");
    EXPECT_EQ(l[1].text, "selective / guidance");
    for (size_t i = 1; i < l.size(); ++i) EXPECT_GE(l[i].x - l[i - 1].x, 13);
    // The same boundary twice (a pass of a plain crex ends its pre-selective crex each time)
    // is said once.
    auto same = stage_labels({{100, "the pre-selective crex"}, {104, "the pre-selective crex"}}, 13);
    ASSERT_EQ(same.size(), 1u);
    EXPECT_EQ(same[0].text, "the pre-selective crex");
}

TEST(ErrorPlot, AxisEndsAtTheRenderAndABudgetFarBeyondIsInTheLegend) {
    std::vector<CurvePoint> curve;
    for (int i = 0; i <= 10; ++i) {
        CurvePoint p;
        p.seconds = 0.01 * i;
        p.rmse = 0.5 / (1 + i), p.relmse = 0.05 / (1 + i), p.flip = 0.3 / (1 + i), p.perr = 80.0 / (1 + i), p.ssim = 0.9;
        p.event = i == 5 ? "end of guidance" : "step";
        curve.push_back(p);
    }
    std::string svg = error_plot_svg(curve, 30.0);
    const std::regex xtick("class=\"xtick\"[^>]*>([0-9.]+)<");
    double last_tick = 0;
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), xtick); it != std::sregex_iterator(); ++it)
        last_tick = std::stod((*it)[1]);
    EXPECT_NEAR(last_tick, 0.1, 1e-9);  // not 30: the axis ends at the render's own 0.1 s
    EXPECT_NE(svg.find("budget 30 s (beyond the axis)"), std::string::npos);
    EXPECT_NE(svg.find("(log)"), std::string::npos);
    EXPECT_NE(svg.find(">0.01<"), std::string::npos);  // a decade tick: absolute values
    EXPECT_EQ(svg.find("its largest value"), std::string::npos);
}

// A plot over frames: a point not measured (the first frame's flicker) is left out, not drawn at
// 0; frame ticks are whole frames; the legend gives each line's mean over its measured points.
TEST(SeriesPlot, LeavesOutWhatWasNotMeasuredAndTicksWholeFrames) {
    PlotSeries flicker{"flicker", "#9334e6", {{10, NAN}, {11, 0.004}, {12, 0.002}, {13, 0.003}}, true};
    const std::string svg = series_plot_svg("quality-plot", "frame", "difference", {flicker});
    EXPECT_NE(svg.find("id=\"quality-plot\""), std::string::npos);
    const std::regex points("points=\"([^\"]*)\"");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(svg, m, points));
    const std::string p = m[1];
    EXPECT_EQ(std::count(p.begin(), p.end(), ','), 3);  // three measured points, frame 10 left out
    EXPECT_NE(svg.find("flicker (mean 0.003)"), std::string::npos) << svg;
    const std::regex xtick("class=\"xtick\"[^>]*>([^<]+)<");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), xtick); it != std::sregex_iterator(); ++it) {
        const double t = std::stod((*it)[1]);
        EXPECT_EQ(t, std::round(t)) << (*it)[1];
        EXPECT_GE(t, 10);
        EXPECT_LE(t, 13);
    }
    size_t circles = 0;
    for (size_t at = svg.find("<circle"); at != std::string::npos; at = svg.find("<circle", at + 1)) ++circles;
    EXPECT_EQ(circles, 3u);
}

TEST(SequenceReport, TheStripHoldsTheFirstAndLastFramesEvenlySpaced) {
    EXPECT_EQ(strip_frames(0, 12), std::vector<size_t>{});
    EXPECT_EQ(strip_frames(1, 12), std::vector<size_t>{0});
    EXPECT_EQ(strip_frames(5, 12), (std::vector<size_t>{0, 1, 2, 3, 4}));
    EXPECT_EQ(strip_frames(61, 5), (std::vector<size_t>{0, 15, 30, 45, 60}));
    const auto many = strip_frames(1000, 12);
    ASSERT_EQ(many.size(), 12u);
    EXPECT_EQ(many.front(), 0u);
    EXPECT_EQ(many.back(), 999u);
    EXPECT_EQ(strip_frames(7, 1), std::vector<size_t>{0});
}

}  // namespace
}  // namespace crex
