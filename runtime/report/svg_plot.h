/// \file svg_plot.h
/// The error-against-time plot of a report, as a standalone SVG: one curve per metric (each
/// scaled to its own largest value, 1 - SSIM for SSIM, so every curve is an error that should
/// fall), stage boundaries as dashed verticals, the budget as a red vertical.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "runtime/report/error_curve.h"

namespace crex {

std::string error_plot_svg(const std::vector<CurvePoint>& curve, std::optional<double> budget_seconds);

}  // namespace crex
