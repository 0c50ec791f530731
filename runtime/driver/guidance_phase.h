/// \file guidance_phase.h
/// Stage 2 of a pipeline (spec/pipeline.md §1), once per round of the cyclic process: every map
/// of the plan computed on the image so far by the stdlib operators (runtime/pipeline/
/// guidance_graph.h), or every map constant under --uniform, and the svt: each selective
/// variable's value per pixel, as the selective stage uses them.
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "compiler/plan/pipeline_plan.h"
#include "runtime/pipeline/pixel_probe.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/shade.h"

namespace crex {

struct RunSettings;
struct RunResult;
struct Scene;

/// `vary ic_rays`' value as it is used: the nearest power of two from 16 to 32768. A record
/// serves pixels that ask for as many rays or fewer, so every shade of a map asking for its own
/// count made records no neighbour would take, and each count is a batch of its own.
uint16_t ic_rays_step(double rays);

/// The per-pixel values the svt gives the selective stage.
struct SelectiveSetup {
    ShadeParams shade;
    std::vector<uint32_t> spp_end;  ///< per pixel: sample index to end at (<= preview spp: none added)
    std::vector<uint16_t> shadow_rays;
    std::vector<uint16_t> media_samples;
    std::vector<float> specular_threshold;
    std::vector<float> ic_accuracy, ic_priority;
    std::vector<uint16_t> ic_divisions;  ///< `vary ic_rays`: each pixel's hemisphere rays a record
    std::vector<float> modulation;  ///< I(p) of `{ }`
};

/// The film buffers the plan's guidance reads: "noise", "direct", "emission", "ambient" and
/// component letters (only these are made: at 1920x1080 all ten took 250 MB).
std::set<std::string> guidance_reads(const PipelinePlan& plan);

/// What guidance is computed for.
struct GuidanceContext {
    const PipelinePlan& plan;
    const Scene& scene;
    const RenderScene& render_scene;
    const RunSettings& settings;
    bool has_cache = false;  ///< the render has an irradiance cache (ic_radius can vary)
};

/// The maps of `ctx.plan` on `image` (with `stand_ins`, the per-pixel ambient stand-ins that go
/// with it, sample-summed) and the svt's values. Records the maps, the sub-sampling grids and
/// what it did not execute (notes) in `out`; `surfaces`: what each pixel centre sees (the
/// task and distractor maps', capict's), probed the first time a round needs it.
/// `grid_stride` > 1: `image` is a preview sampled at that stride; the maps of what pixels see
/// are made on its grid and spread over the frame (guidance_grid.h).
SelectiveSetup run_guidance(const GuidanceContext& ctx, const std::vector<float>& image, const std::vector<double>& stand_ins,
                            RunResult& out, std::optional<PixelProbe>& surfaces, uint32_t grid_stride = 1);

}  // namespace crex
