/// \file guidance_graph.h
/// Evaluates the guidance part of a plan: each typed map definition (PipelinePlan::maps, and
/// the preview and buffers it reads) becomes a raster, computed once, in dependency order, by
/// the stdlib operators of stdlib/guidance, bound per pipeline::GuidanceOperator in a switch. Operators see linear buffers through one tone map (spec
/// §7): the preview's exposure applied to every buffer, then the display curve.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "compiler/plan/pipeline_plan.h"
#include "runtime/pipeline/guidance_grid.h"
#include "runtime/pipeline/pixel_probe.h"
#include "runtime/scene/scene.h"
#include "stdlib/guidance/raster.h"

namespace crex {

struct GuidanceInputs {
    int width = 0, height = 0;
    std::vector<float> preview;                           ///< linear RGB
    std::map<std::string, std::vector<float>> buffers;    ///< "direct", "emission", "ambient", "D".."M": linear RGB
    const Scene* scene = nullptr;
    const PixelProbe* probe = nullptr;
    /// Set after a strided preview: `probe` is of this grid's pixels, and the maps of what the
    /// pixels see (task map, distractors, X-map) are made on the grid and spread over the frame.
    const GuidanceGrid* grid = nullptr;
};

class GuidanceGraph {
public:
    GuidanceGraph(const PipelinePlan& plan, GuidanceInputs inputs);
    /// The raster of node `id`: "preview", a buffer, or a map (one channel in [0, 1]). Throws std::runtime_error for a
    /// plan this runtime cannot evaluate (unknown operator, missing input).
    const guidance::Raster& map(const std::string& id);
    /// Every map evaluated so far, by node id.
    const std::map<std::string, guidance::Raster>& evaluated() const { return memo_; }

private:
    guidance::Raster evaluate(const PlanMap& node);
    bool is_objects(const std::string& id) const;
    guidance::Raster display(const std::vector<float>& linear) const;
    std::vector<bool> objects(const std::string& id);
    guidance::Raster as_map(const guidance::Raster& r) const;

    const PipelinePlan& plan_;
    GuidanceInputs in_;
    double exposure_ = 1;
    std::map<std::string, guidance::Raster> memo_;
    std::vector<std::string> evaluating_;
};

}  // namespace crex
