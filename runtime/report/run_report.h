/// \file run_report.h
/// `crex run --report DIR`: the run's checkpoints as JSON and CSV, the error-against-time plot
/// (SVG), the images (final, preview, maps, per-pixel pictures, components) as PNGs, the plan
/// graph, and index.html holding all of it in one self-contained page.
#pragma once

#include <nlohmann/json.hpp>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "runtime/metrics/metrics.h"
#include "runtime/report/checkpoints.h"
#include "runtime/report/error_curve.h"
#include "stdlib/guidance/raster.h"

namespace crex {

struct RunReport {
    std::string dir;
    std::string title;
    int width = 0, height = 0;
    const std::vector<Checkpoint>* checkpoints = nullptr;
    std::optional<metrics::Image> reference;
    std::string reference_path;
    metrics::DisplayView view;
    std::optional<double> budget_seconds;
    nlohmann::json summary;                                          ///< the run's JSON summary
    std::vector<std::pair<std::string, std::vector<float>>> images;  ///< title, linear RGB (final first)
    std::vector<std::pair<std::string, guidance::Raster>> maps;
    std::vector<std::string> pictures;                               ///< PNGs already written (--maps)
    std::map<std::string, std::pair<double, std::string>> picture_scales;  ///< heat pictures: path -> max, unit
    std::string plan_dot;
    std::string policy;  ///< the budget policy this run used
    /// The same render under the other policies: drawn with this one on one plot.
    std::vector<std::pair<std::string, const std::vector<Checkpoint>*>> other_policies;
    /// `--equal-time`: the pipeline's image and uniform rendering's in the same time (linear
    /// RGB), with their FLIP maps against the reference; shown as a pair, `note` above them.
    struct EqualTime {
        std::string pipeline_title, uniform_title, note;
        std::vector<float> pipeline, uniform, pipeline_flip, uniform_flip;
    };
    std::optional<EqualTime> equal_time;
};

/// "" when `dir` may become a report, replacing what it holds: it does not exist, is an empty
/// folder, or holds a crex report (its index.html carries kReportMarker); else why not. A run
/// asks before rendering, so a folder of the user's own is never removed.
std::string report_folder_refusal(const std::string& dir);

/// A component image's caption: its light (summed luminance) as a share of the final image's,
/// e.g. "12.5 % of the image's light"; "" when the final image holds no light.
std::string light_share_note(double part, double whole);

/// Writes the report into `report.dir` (a fresh folder); returns "" or what failed. `curve`
/// receives the error curve.
std::string write_run_report(const RunReport& report, std::vector<CurvePoint>& curve);

}  // namespace crex
