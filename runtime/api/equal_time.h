/// \file equal_time.h
/// `crex run PIPELINE --equal-time`: the comparison selective rendering lives or dies by, made
/// in one command. Uniform rendering (the default crex, every pixel alike, through the cache
/// when the pipeline uses one) gets the pipeline's render time as its budget; both images are
/// then scored against the reference: FLIP, and FLIP weighted by where a viewer looks (the
/// pipeline's own task map, else the reference's saliency).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "compiler/plan/pipeline_plan.h"
#include "runtime/driver/run_plan.h"
#include "runtime/metrics/image_comparison.h"

namespace crex {

/// The uniform render made in the pipeline's time.
struct EqualTimeRun {
    std::string crex;                 ///< what it rendered (every pixel alike)
    bool irradiance_cache = false;    ///< D through the cache, as the pipeline's
    double budget_seconds = 0;        ///< the pipeline's render time
    double render_seconds = 0;        ///< what the uniform render took
    double mean_spp = 0;              ///< camera samples per pixel it reached, on average
    uint32_t min_spp = 0, max_spp = 0;
    std::vector<float> image;         ///< linear RGB
};

/// Renders the default crex over `scene` with the pipeline's size, seed, limits and cache
/// settings (`pipeline`, as resolved) under a budget of `seconds`, progressive passes, as many
/// samples as fit.
EqualTimeRun render_uniform_in_equal_time(const Scene& scene, const RunSettings& pipeline, double seconds);

/// Both images against the reference, as a viewer sees them (the reference's exposure).
struct EqualTimeScore {
    std::string attention;                   ///< what the weights are: "task map 'NAME'" or "the reference's saliency"
    metrics::ImageComparison pipeline, uniform;  ///< FLIP, aFLIP, RMSE, with FLIP maps
    metrics::DisplayView view;
};

/// Per-pixel weights of where a viewer looks at `display_rgb` (tone-mapped RGB): its Itti-Koch
/// saliency; every pixel alike where nothing stands out.
std::vector<float> saliency_weights(const metrics::Image& display_rgb);

/// The attention weights: the first task map the plan defines and the run kept (`maps`), else
/// the reference's saliency. `attention` says which.
std::vector<float> equal_time_attention(const PipelinePlan& plan, const std::vector<std::pair<std::string, guidance::Raster>>& maps,
                                        const metrics::Image& reference, const metrics::DisplayView& view, std::string& attention);

EqualTimeScore score_equal_time(const std::vector<float>& pipeline_image, const EqualTimeRun& uniform, const metrics::Image& reference,
                                const std::vector<float>& weights, std::string attention);

/// The summary's "equal_time" object.
nlohmann::json equal_time_json(const EqualTimeRun& uniform, const EqualTimeScore& score);

/// The lines `crex run` prints for it (from equal_time_json()).
void print_equal_time(const nlohmann::json& j, std::ostream& out);

}  // namespace crex
