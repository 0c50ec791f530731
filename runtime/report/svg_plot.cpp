#include "runtime/report/svg_plot.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace crex {

std::vector<double> nice_ticks(double max, int about) {
    std::vector<double> out;
    if (!(max > 0) || !std::isfinite(max) || about < 1) return {0};
    // The step: 1, 2 or 5 times a power of ten, the largest giving about `about` intervals.
    const double raw = max / about, decade = std::pow(10.0, std::floor(std::log10(raw)));
    double step = decade;
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * decade <= raw * 1.5) step = m * decade;
    for (int k = 0; k * step <= max * (1 + 1e-9); ++k) out.push_back(k * step);
    return out;
}

std::string tick_label(double v) {
    if (v == 0) return "0";
    std::string s = fmt::format("{:.6g}", v);
    return s;
}

std::vector<StageLabel> stage_labels(const std::vector<std::pair<double, std::string>>& boundaries, double min_gap) {
    std::vector<StageLabel> out;
    for (const auto& [x, text] : boundaries) {
        if (!out.empty() && x - out.back().x < min_gap) {
            // Too close to draw apart: one label for both (once, if they say the same).
            if (out.back().text.find(text) == std::string::npos) out.back().text += " / " + text;
            continue;
        }
        out.push_back({x, text});
    }
    return out;
}

namespace {

// An <svg> of W x H with a white ground and the two axes of a plot area (left, top, pw x ph).
std::string svg_frame(const std::string& id, double W, double H, double left, double top, double pw, double ph) {
    std::string svg = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"{}\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\" "
        "font-family=\"Helvetica,Arial,sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
        id, W, H, W, H);
    svg += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"black\"/>\n", left, top, top + ph);
    svg += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"black\"/>\n", left, top + ph, left + pw);
    return svg;
}

// A legend row right of the plot area (which ends at x0), at height y.
std::string legend_entry(double x0, double y, const std::string& colour, const std::string& text, const std::string& legend_id) {
    return fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"{3}\" stroke-width=\"3\"/>\n", x0 + 12, y, x0 + 32, colour) +
           fmt::format("<text{} x=\"{}\" y=\"{}\">{}</text>\n", legend_id.empty() ? "" : " id=\"" + legend_id + "\"", x0 + 38, y + 4, text);
}

// A mean as people read it: 1052 as "1052", 0.0037634 as "0.00376".
std::string mean_text(double v) { return std::fabs(v) >= 100 ? fmt::format("{:.0f}", v) : fmt::format("{:.3g}", v); }

struct PlotLine {
    std::string name, colour;
    std::vector<std::pair<double, double>> points;  ///< (seconds, error); non-finite errors skipped
};

// Errors in (0, 1] against time: a log y axis over the decades the lines span, a time axis
// ending at the lines' own end (a 0.1 s render under a 30 s budget was a squashed line against
// the axis; a budget beyond it is said in the legend), dashed verticals with upright labels at
// `stage_marks` (seconds, text), the budget as a red vertical.
std::string log_plot_svg(const std::string& id, const std::string& y_label, const std::vector<PlotLine>& lines,
                         std::optional<double> budget, const std::vector<std::pair<double, std::string>>& stage_marks) {
    const double W = 720, H = 380, left = 64, right = 190, top = 20, bottom = 50;
    const double pw = W - left - right, ph = H - top - bottom;
    double tend = 1e-9;
    for (const auto& l : lines)
        for (const auto& [t, v] : l.points) tend = std::max(tend, t);
    const bool budget_on_axis = budget && *budget <= tend * 1.25;
    if (budget_on_axis) tend = std::max(tend, *budget);
    const std::vector<double> xt = nice_ticks(tend, 5);
    const double tmax = std::max(tend, xt.back());
    auto x = [&](double t) { return left + pw * t / tmax; };
    double lo = 1, hi = 1e-9;
    for (const auto& l : lines)
        for (const auto& [t, v] : l.points)
            if (std::isfinite(v) && v > 0) lo = std::min(lo, v), hi = std::max(hi, v);
    const int d0 = static_cast<int>(std::floor(std::log10(std::max(lo, 1e-6)))),
              d1 = std::max(d0 + 1, static_cast<int>(std::ceil(std::log10(std::max(hi, 1e-6)))));
    auto y = [&](double v) {
        double l = std::log10(std::clamp(v, std::pow(10.0, d0), std::pow(10.0, d1)));
        return top + ph * (1 - (l - d0) / (d1 - d0));
    };

    std::string svg = svg_frame(id, W, H, left, top, pw, ph);
    for (double t : xt)
        svg += fmt::format("<text class=\"xtick\" x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", x(t), top + ph + 16, tick_label(t));
    for (int d = d0; d <= d1; ++d) {
        const double v = std::pow(10.0, d);
        svg += fmt::format("<text class=\"ytick\" x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{}</text>\n", left - 6, y(v) + 4, tick_label(v));
        svg += fmt::format("<line x1=\"{0}\" y1=\"{1:.1f}\" x2=\"{2}\" y2=\"{1:.1f}\" stroke=\"#ddd\"/>\n", left + 1, y(v), left + pw);
        if (d < d1)
            for (double m : {2.0, 5.0})
                svg += fmt::format("<line x1=\"{0}\" y1=\"{1:.1f}\" x2=\"{2}\" y2=\"{1:.1f}\" stroke=\"#f3f3f3\"/>\n", left + 1, y(m * v), left + pw);
    }
    svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">render time (s)</text>\n", left + pw / 2, H - 12);
    svg += fmt::format("<text x=\"16\" y=\"{}\" text-anchor=\"middle\" transform=\"rotate(-90 16 {})\">{}</text>\n", top + ph / 2,
                       top + ph / 2, y_label);
    // Stage boundaries: dashed verticals, labelled upright along them; boundaries too close to
    // label apart share one label.
    std::vector<std::pair<double, std::string>> boundaries;
    for (const auto& [t, text] : stage_marks) boundaries.push_back({x(t), text});
    for (const auto& [bx, text] : boundaries)
        svg += fmt::format("<line class=\"stage\" x1=\"{0:.1f}\" y1=\"{1}\" x2=\"{0:.1f}\" y2=\"{2}\" stroke=\"#888\" stroke-dasharray=\"4 3\"/>\n",
                           bx, top, top + ph);
    for (const auto& l : stage_labels(boundaries, 13))
        svg += fmt::format("<text class=\"stage-label\" x=\"{0:.1f}\" y=\"{1}\" fill=\"#555\" font-size=\"10\" "
                           "transform=\"rotate(-90 {0:.1f} {1})\" text-anchor=\"end\">end of {2}</text>\n",
                           l.x + 10, top + 4, l.text);
    int row = 0;
    auto legend = [&](const std::string& colour, const std::string& text, const std::string& legend_id) {
        svg += legend_entry(left + pw, top + 14 + 18 * row++, colour, text, legend_id);
    };
    for (const auto& l : lines) {
        std::string pts;
        double last = NAN;
        for (const auto& [t, v] : l.points)
            if (std::isfinite(v)) pts += fmt::format("{:.2f},{:.2f} ", x(t), y(v)), last = v;
        if (pts.empty()) continue;
        svg += fmt::format("<polyline class=\"curve\" data-metric=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\" points=\"{}\"/>\n",
                           l.name, l.colour, pts);
        legend(l.colour, fmt::format("{} (end {:.3g})", l.name, last), "");
    }
    if (budget) {
        if (budget_on_axis)
            svg += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1}\" x2=\"{0:.1f}\" y2=\"{2}\" stroke=\"#d93025\" stroke-width=\"2\"/>\n",
                               x(*budget), top, top + ph);
        legend("#d93025", fmt::format("budget {:g} s{}", *budget, budget_on_axis ? "" : " (beyond the axis)"), "budget");
    }
    svg += "</svg>\n";
    return svg;
}

}  // namespace

std::string error_plot_svg(const std::vector<CurvePoint>& curve, std::optional<double> budget) {
    struct Series {
        const char* name;
        const char* colour;
        std::function<double(const CurvePoint&)> value;
    };
    // Absolute errors on one log axis: every metric here lies in (0, 1] (perr as a fraction).
    const Series series[] = {
        {"rmse", "#1a73e8", [](const CurvePoint& p) { return p.rmse; }},
        {"relmse", "#9334e6", [](const CurvePoint& p) { return p.relmse; }},
        {"flip", "#e37400", [](const CurvePoint& p) { return p.flip; }},
        {"perr / 100", "#188038", [](const CurvePoint& p) { return p.perr / 100; }},
        {"1 - ssim", "#c5221f", [](const CurvePoint& p) { return p.ssim ? 1 - *p.ssim : NAN; }},
    };
    std::vector<PlotLine> lines;
    for (const auto& s : series) {
        PlotLine l{s.name, s.colour, {}};
        for (const auto& p : curve) l.points.push_back({p.seconds, s.value(p)});
        lines.push_back(std::move(l));
    }
    std::vector<std::pair<double, std::string>> marks;
    for (const auto& p : curve)
        if (p.event.rfind("end of ", 0) == 0 && p.event != "end of render") marks.push_back({p.seconds, p.event.substr(7)});
    return log_plot_svg("error-plot", "error against the reference (log)", lines, budget, marks);
}

std::string policy_plot_svg(const std::vector<std::pair<std::string, std::vector<CurvePoint>>>& runs, std::optional<double> budget) {
    static const char* colours[] = {"#1a73e8", "#e37400", "#188038", "#9334e6", "#c5221f", "#5f6368"};
    std::vector<PlotLine> lines;
    for (size_t i = 0; i < runs.size(); ++i) {
        PlotLine l{runs[i].first, colours[i % std::size(colours)], {}};
        for (const auto& p : runs[i].second) l.points.push_back({p.seconds, p.flip});
        lines.push_back(std::move(l));
    }
    return log_plot_svg("policy-plot", "FLIP against the reference (log)", lines, budget, {});
}

std::string series_plot_svg(const std::string& id, const std::string& x_label, const std::string& y_label, const std::vector<PlotSeries>& series) {
    const double W = 760, H = 300, left = 64, right = 240, top = 20, bottom = 50;
    const double pw = W - left - right, ph = H - top - bottom;
    double x0 = INFINITY, x1 = -INFINITY, ymax = 0;
    for (const auto& s : series)
        for (const auto& [px, py] : s.points) {
            x0 = std::min(x0, px), x1 = std::max(x1, px);
            if (std::isfinite(py)) ymax = std::max(ymax, py);
        }
    if (!(x0 <= x1)) x0 = 0, x1 = 1;
    if (x1 - x0 < 1) x1 = x0 + 1;  // one frame: a point in the middle of a unit span
    const std::vector<double> yt = nice_ticks(ymax > 0 ? ymax : 1, 4);
    const double ytop = std::max(yt.back(), ymax > 0 ? ymax : 1);
    // Frame ticks: whole numbers in 1-2-5 steps from the first frame.
    std::vector<double> xt;
    for (double t : nice_ticks(x1 - x0, 6))
        if (t == std::round(t)) xt.push_back(x0 + t);
    auto x = [&](double v) { return left + pw * (v - x0) / (x1 - x0); };
    auto y = [&](double v) { return top + ph * (1 - std::clamp(v, 0.0, ytop) / ytop); };
    std::string svg = svg_frame(id, W, H, left, top, pw, ph);
    for (double t : xt)
        svg += fmt::format("<text class=\"xtick\" x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", x(t), top + ph + 16, tick_label(t));
    for (double v : yt) {
        svg += fmt::format("<text class=\"ytick\" x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{}</text>\n", left - 6, y(v) + 4, tick_label(v));
        if (v > 0) svg += fmt::format("<line x1=\"{0}\" y1=\"{1:.1f}\" x2=\"{2}\" y2=\"{1:.1f}\" stroke=\"#ddd\"/>\n", left + 1, y(v), left + pw);
    }
    svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", left + pw / 2, H - 12, x_label);
    svg += fmt::format("<text x=\"16\" y=\"{}\" text-anchor=\"middle\" transform=\"rotate(-90 16 {})\">{}</text>\n", top + ph / 2,
                       top + ph / 2, y_label);
    int row = 0;
    for (const auto& s : series) {
        std::string pts, dots;
        double sum = 0;
        size_t n = 0;
        for (const auto& [px, py] : s.points) {
            if (!std::isfinite(py)) continue;
            pts += fmt::format("{:.2f},{:.2f} ", x(px), y(py));
            if (s.dots) dots += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"3\" fill=\"{}\"/>\n", x(px), y(py), s.colour);
            sum += py, ++n;
        }
        if (n == 0) continue;
        svg += fmt::format("<polyline class=\"curve\" data-series=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\"{} points=\"{}\"/>\n",
                           s.name, s.colour, s.dashed ? 1.5 : 2, s.dashed ? " stroke-dasharray=\"5 4\"" : "", pts) + dots;
        svg += legend_entry(left + pw, top + 14 + 18 * row++, s.colour, fmt::format("{} (mean {})", s.name, mean_text(sum / static_cast<double>(n))), "");
    }
    svg += "</svg>\n";
    return svg;
}

}  // namespace crex
