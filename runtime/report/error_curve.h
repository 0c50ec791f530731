/// \file error_curve.h
/// The error of every checkpoint against a reference image: scored when the checkpoint is taken
/// (scorer_against), gathered into a curve after the render.
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

/// What a checkpoint's image scores against `reference` shown through `view`: RMSE and relMSE
/// of the linear images, mean FLIP, the share of pixels whose FLIP is over `perr_threshold`,
/// SSIM of the displayed images. The reference's display image is made once, here.
CheckpointScorer scorer_against(const metrics::Image& reference, const metrics::DisplayView& view,
                                double perr_threshold = metrics::kDefaultPerrThreshold);

/// `view`: how both images are shown to the perceptual metrics (the reference's exposure). A
/// checkpoint scored when taken keeps its score (made with the same reference and view); one
/// that still holds its image is scored here.
std::vector<CurvePoint> error_curve(const std::vector<Checkpoint>& checkpoints, const metrics::Image& reference,
                                    const metrics::DisplayView& view, double perr_threshold = metrics::kDefaultPerrThreshold);

/// CSV with a header row: seconds,stage,event,rays,rmse,relmse,flip,perr,ssim.
std::string curve_csv(const std::vector<CurvePoint>& curve);

}  // namespace crex
