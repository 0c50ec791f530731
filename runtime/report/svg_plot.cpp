#include "runtime/report/svg_plot.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace crex {

std::string error_plot_svg(const std::vector<CurvePoint>& curve, std::optional<double> budget) {
    const double W = 720, H = 360, left = 60, right = 170, top = 20, bottom = 50;
    const double pw = W - left - right, ph = H - top - bottom;
    double tmax = 1e-9;
    for (const auto& p : curve) tmax = std::max(tmax, p.seconds);
    if (budget) tmax = std::max(tmax, *budget);
    tmax *= 1.05;
    auto x = [&](double t) { return left + pw * t / tmax; };
    auto y = [&](double v) { return top + ph * (1 - std::clamp(v, 0.0, 1.0)); };
    std::string svg = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"error-plot\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\" "
        "font-family=\"Helvetica,Arial,sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
        W, H, W, H);
    // Axes and ticks.
    svg += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"black\"/>\n", left, top, top + ph);
    svg += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"black\"/>\n", left, top + ph, left + pw);
    for (int i = 0; i <= 5; ++i) {
        double t = tmax * i / 5, v = i / 5.0;
        svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{:.3g}</text>\n", x(t), top + ph + 16, t);
        svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{:.1f}</text>\n", left - 6, y(v) + 4, v);
        svg += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"#eee\"/>\n", left + 1, y(v), left + pw);
    }
    svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">render time (s)</text>\n", left + pw / 2, H - 12);
    svg += fmt::format("<text x=\"14\" y=\"{}\" text-anchor=\"middle\" transform=\"rotate(-90 14 {})\">error / its largest value</text>\n",
                       top + ph / 2, top + ph / 2);
    // Stage boundaries, labelled with the stage that ended (staggered so close ones stay legible).
    int boundary = 0;
    for (const auto& p : curve)
        if (p.event.rfind("end of ", 0) == 0 && p.event != "end of render") {
            svg += fmt::format("<line class=\"stage\" x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"#888\" stroke-dasharray=\"4 3\"/>\n",
                               x(p.seconds), top, top + ph);
            svg += fmt::format("<text x=\"{}\" y=\"{}\" fill=\"#555\" font-size=\"10\">end of {}</text>\n", x(p.seconds) + 3,
                               top + ph - 8 - 12 * (boundary++ % 3), p.stage);
        }
    if (budget) {
        svg += fmt::format("<line id=\"budget\" x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"#d93025\" stroke-width=\"2\"/>\n",
                           x(*budget), top, top + ph);
        svg += fmt::format("<text x=\"{}\" y=\"{}\" fill=\"#d93025\">budget {:.3g} s</text>\n", x(*budget) + 4, top + ph - 6, *budget);
    }
    struct Series {
        const char* name;
        const char* colour;
        std::function<double(const CurvePoint&)> value;
    };
    const Series series[] = {
        {"rmse", "#1a73e8", [](const CurvePoint& p) { return p.rmse; }},
        {"relmse", "#9334e6", [](const CurvePoint& p) { return p.relmse; }},
        {"flip", "#e37400", [](const CurvePoint& p) { return p.flip; }},
        {"perr", "#188038", [](const CurvePoint& p) { return p.perr; }},
        {"1 - ssim", "#c5221f", [](const CurvePoint& p) { return p.ssim ? 1 - *p.ssim : NAN; }},
    };
    int row = 0;
    for (const auto& s : series) {
        double mx = 0;
        for (const auto& p : curve)
            if (std::isfinite(s.value(p))) mx = std::max(mx, s.value(p));
        if (!(mx > 0)) continue;
        std::string pts;
        for (const auto& p : curve)
            if (std::isfinite(s.value(p))) pts += fmt::format("{:.2f},{:.2f} ", x(p.seconds), y(s.value(p) / mx));
        svg += fmt::format("<polyline class=\"curve\" data-metric=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\" points=\"{}\"/>\n",
                           s.name, s.colour, pts);
        double ly = top + 14 + 18 * row++;
        svg += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"{3}\" stroke-width=\"3\"/>\n", left + pw + 12, ly,
                           left + pw + 32, s.colour);
        svg += fmt::format("<text x=\"{}\" y=\"{}\">{} (max {:.3g})</text>\n", left + pw + 38, ly + 4, s.name, mx);
    }
    svg += "</svg>\n";
    return svg;
}

}  // namespace crex
