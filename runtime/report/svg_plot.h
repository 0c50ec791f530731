/// \file svg_plot.h
/// The error-against-time plot of a report, as a standalone SVG: one curve per metric, absolute
/// errors on one log axis (1 - SSIM for SSIM, perr as a fraction, so every curve is an error in
/// (0, 1] that should fall), the time axis ending at the render's own time with 1-2-5 ticks,
/// stage boundaries as dashed verticals with upright labels, the budget as a red vertical (or
/// in the legend when it lies far beyond the render).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "runtime/report/error_curve.h"

namespace crex {

std::string error_plot_svg(const std::vector<CurvePoint>& curve, std::optional<double> budget_seconds);

/// The same axes with one FLIP curve per run (policy name, its curve): every budget policy's
/// error against time on one plot (crex run --compare-policies).
std::string policy_plot_svg(const std::vector<std::pair<std::string, std::vector<CurvePoint>>>& runs, std::optional<double> budget_seconds);

/// One line of a plot over frames: (x, y) points in order; points whose y is not finite are
/// left out (the line joins its neighbours), each point is marked when `dots`.
struct PlotSeries {
    std::string name, colour;
    std::vector<std::pair<double, double>> points;
    bool dots = false;
    bool dashed = false;
};

/// Values against frame number on linear axes (y from 0 past the largest value), as a
/// standalone SVG with the given id; each series in the legend with its mean.
std::string series_plot_svg(const std::string& id, const std::string& x_label, const std::string& y_label, const std::vector<PlotSeries>& series);

/// Round axis ticks from 0 past `max`: steps of 1, 2 or 5 times a power of ten, about `about`
/// of them; and how a tick is written (no trailing zeros: 0.2, 1.5, 10).
std::vector<double> nice_ticks(double max, int about);
std::string tick_label(double v);

/// Stage-boundary labels at x positions (pixels, increasing): boundaries closer than
/// `min_gap` to the previous label share it ("guidance / selective"), so no two overlap.
struct StageLabel {
    double x;
    std::string text;
};
std::vector<StageLabel> stage_labels(const std::vector<std::pair<double, std::string>>& boundaries, double min_gap);

}  // namespace crex
