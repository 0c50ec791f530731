/// \file error_curve.h
/// The error of every checkpoint against a reference image, computed after the render.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "runtime/metrics/metrics.h"
#include "runtime/report/checkpoints.h"

namespace crex {

struct CurvePoint {
    double seconds = 0;
    std::string stage, event;
    uint64_t rays = 0;
    double rmse = 0, relmse = 0, flip = 0, perr = 0;
    std::optional<double> ssim;
};

/// `view`: how both images are shown to the perceptual metrics (the reference's exposure).
std::vector<CurvePoint> error_curve(const std::vector<Checkpoint>& checkpoints, const metrics::Image& reference,
                                    const metrics::DisplayView& view, double perr_threshold = metrics::kDefaultPerrThreshold);

/// CSV with a header row: seconds,stage,event,rays,rmse,relmse,flip,perr,ssim.
std::string curve_csv(const std::vector<CurvePoint>& curve);

}  // namespace crex
