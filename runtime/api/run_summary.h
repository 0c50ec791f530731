/// \file run_summary.h
/// What `crex run` says when it is done: the JSON summary (--format json, and the report's
/// summary table) and the text table for people.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "runtime/report/run_pictures.h"
#include "runtime/render/profile.h"
#include "compiler/plan/pipeline_plan.h"
#include "runtime/api/run_options.h"
#include "runtime/driver/run_plan.h"
#include "runtime/report/checkpoints.h"
#include "runtime/report/error_curve.h"

namespace crex {

/// Everything one run did, as the summaries need it. Pointers are null when not applicable.
struct RunFacts {
    std::string scene;
    const sched::Program* program = nullptr;
    int width = 0, height = 0;
    uint32_t spp = 0;
    double load_seconds = 0;
    const RunResult* result = nullptr;
    const RunResult* piped = nullptr;  ///< with the plan it ran
    const PipelinePlan* plan = nullptr;
    std::vector<std::string> outputs;
    double budget = 0;
    const CheckpointRecorder* recorder = nullptr;
    const IcSettings* ic = nullptr;
    size_t ic_loaded = 0;
    std::string ic_file;  ///< --ic-file: where the cache was loaded from and saved to
    std::string maps_dir;
    const PictureSummary* pictures = nullptr;
    const std::vector<CurvePoint>* curve = nullptr;
    std::string reference;
    std::string report_dir;
    const Profile* predicted = nullptr;  ///< the --profile the run predicted from
    uint32_t preview_stride = 1;         ///< the preview at every k-th pixel
    double budget_floor = 0;             ///< the smallest budget the pipeline can meet (0: unknown)
    bool below_floor = false;            ///< rendered under a budget below it (--budget-floor ok)
    const nlohmann::json* load_warnings = nullptr;  ///< RunInputs::load_warnings, listed before the run's
};

/// Per component (and "camera"): how far the profile's cost per ray was from this run's
/// measured cost, in % of the measured (thesis Table 5.4); only what both know.
std::vector<std::pair<std::string, double>> profile_errors(const Profile& predicted, const ExecutorStats& measured);

nlohmann::json run_summary_json(const RunFacts& f);
void print_run_summary(const RunFacts& f, std::ostream& out);

/// W404 for each limit that left out more than kLightLeftOutWarning of the image's light
/// (RunResult::light_cut_by_*): where the limit was set (the pipeline's line, else the
/// command line) and which flag raises it.
inline constexpr double kLightLeftOutWarning = 0.01;
std::vector<Diagnostic> light_left_out_warnings(const RunResult& r, const ShadeParams& shade, const IcSettings* ic,
                                                 const LimitOrigins& origins);

/// The error curve's entries for the JSON summary.
nlohmann::json curve_json(const std::vector<CurvePoint>& curve);

}  // namespace crex
