#include "runtime/pipeline/guidance_graph.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "base/check.h"
#include "runtime/io/image_io.h"
#include "runtime/pipeline/svt.h"
#include "stdlib/guidance/filters.h"
#include "stdlib/guidance/operators.h"

namespace crex {
namespace {

using guidance::Raster;

constexpr double kDefaultFovea = 2 * std::numbers::pi / 180;  // 2 degrees: the fovea

}  // namespace

GuidanceGraph::GuidanceGraph(const PipelinePlan& plan, GuidanceInputs inputs) : plan_(plan), in_(std::move(inputs)) {
    exposure_ = display_exposure(in_.preview);
}

Raster GuidanceGraph::display(const std::vector<float>& linear) const {
    Raster r(in_.width, in_.height, 3);
    // In parallel: the sRGB curve's pow was a third of a small pipeline's guidance (7.5 ms of
    // 24 at 384x288). Each value is its own, so the split changes no bit.
    CREX_CHECK_EQ(linear.size(), r.v.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, linear.size(), 1 << 14), [&](const tbb::blocked_range<size_t>& b) {
        to_display(linear.data() + b.begin(), r.v.data() + b.begin(), b.size(), exposure_);
    });
    return r;
}

Raster GuidanceGraph::as_map(const Raster& r) const {
    if (r.channels == 1) return r;
    Raster y = guidance::luminance(r);
    guidance::clamp01(y);
    return y;
}

const Raster& GuidanceGraph::map(const std::string& id) {
    if (auto it = memo_.find(id); it != memo_.end()) return it->second;
    if (id == "preview") return memo_[id] = display(in_.preview);
    if (const PlanBuffer* b = find_buffer(plan_, id)) {
        auto it = in_.buffers.find(b->buffer);
        if (it == in_.buffers.end()) throw std::runtime_error("no buffer '" + b->buffer + "' for " + id);
        return memo_[id] = display(it->second);
    }
    const PlanMap* m = find_map(plan_, id);
    if (!m) throw std::runtime_error("the plan has no map, buffer or preview '" + id + "'");
    if (std::find(evaluating_.begin(), evaluating_.end(), id) != evaluating_.end())
        throw std::runtime_error("the plan's maps depend on each other in a cycle through '" + id + "'");
    evaluating_.push_back(id);
    Raster r = evaluate(*m);
    evaluating_.pop_back();
    return memo_[id] = std::move(r);
}

std::vector<bool> GuidanceGraph::objects(const std::string& id) {
    const PlanMap* m = find_map(plan_, id);
    const auto& shapes = in_.scene->shapes;
    std::vector<bool> out(shapes.size(), false);
    std::string name = m && m->params.tag ? *m->params.tag : "";
    for (size_t s = 0; s < shapes.size(); ++s)
        out[s] = shapes[s].tag && (name.empty() || shapes[s].tag->name == name);
    return out;
}

bool GuidanceGraph::is_objects(const std::string& id) const {
    const PlanMap* m = find_map(plan_, id);
    return m && m->op == pipeline::GuidanceOperator::kTagged;
}

Raster GuidanceGraph::evaluate(const PlanMap& node) {
    const int w = in_.width, h = in_.height;
    const std::vector<PlanMapInput>& inputs = node.inputs;
    // The k-th input that is a picture or map (tagged objects are read by objects()).
    auto input = [&](size_t k) -> Raster {
        size_t seen = 0;
        for (const PlanMapInput& in : inputs)
            if (!is_objects(in.node) && seen++ == k) return map(in.node);
        throw std::runtime_error(fmt::format("{} has no input {}", node.name, k + 1));
    };
    if (!node.op) return as_map(input(0));  // `m = other`: an alias
    const pipeline::GuidanceOperator op = *node.op;
    const std::string_view op_name = pipeline::name_of(op);
    const PlanMapParams& params = node.params;
    if (pipeline::signature(op).needs_scene && (!in_.scene || !in_.probe)) throw std::runtime_error(node.name + " needs the scene");
    // A map of what the probe's pixels see, over the frame: spread when they are a grid's.
    auto on_frame = [&](Raster m) { return in_.grid ? in_.grid->spread(m) : m; };
    // One case per pipeline::GuidanceOperator, no default: -Werror=switch (CMakeLists.txt) makes a
    // new operator without an implementation here a compile error.
    using G = pipeline::GuidanceOperator;
    switch (op) {
    case G::kComponent:
    case G::kTagged:
        throw std::runtime_error(fmt::format("{}: {}() gives a buffer or objects, not a map", node.name, op_name));
    case G::kSaliency: return guidance::saliency(input(0));
    case G::kEdges: return guidance::edges(input(0));
    case G::kRadianceDifference: return guidance::radiance_difference(input(0));
    case G::kConstant: return guidance::constant_map(w, h, params.constant.value_or(0));
    case G::kNormalise: {
        Raster m = as_map(input(0));
        guidance::normalise_max(m);
        return m;
    }
    case G::kBlur: {
        Raster m = guidance::gaussian_blur(as_map(input(0)), params.sigma.value_or(2));
        guidance::clamp01(m);
        return m;
    }
    case G::kThreshold: return guidance::threshold(as_map(input(0)), params.at.value_or(0.5));
    case G::kImportance: {
        std::vector<Raster> maps;
        std::vector<double> weights;
        for (const PlanMapInput& in : inputs) {
            maps.push_back(as_map(map(in.node)));
            weights.push_back(in.weight.value_or(1.0));
        }
        std::vector<const Raster*> ptrs;
        for (const auto& m : maps) ptrs.push_back(&m);
        if (ptrs.empty()) return Raster(w, h, 1);
        return guidance::importance(ptrs, weights, params.combine.value_or("+"));
    }
    case G::kTaskMap: {
        const PixelProbe& probe = *in_.probe;
        const guidance::ViewGeometry view{probe.width, probe.height, in_.scene->camera.view_distance};
        std::vector<bool> selected;
        bool named = false;
        for (const PlanMapInput& in : inputs)
            if (is_objects(in.node)) {
                selected = objects(in.node);
                const PlanMap* t = find_map(plan_, in.node);
                named = t && t->params.tag && !t->params.tag->empty();
            }
        if (selected.empty()) selected = objects("");
        // One set per task value (thesis: 0..3): value = task / 3; an object named explicitly
        // counts even with task 0.
        std::vector<std::vector<bool>> covered(3, std::vector<bool>(probe.shape.size(), false));
        std::vector<double> value = {1.0 / 3, 2.0 / 3, 1.0};
        for (size_t p = 0; p < probe.shape.size(); ++p) {
            int s = probe.shape[p];
            if (s < 0 || !selected[static_cast<size_t>(s)]) continue;
            int task = in_.scene->shapes[static_cast<size_t>(s)].tag->task;
            if (task <= 0 && named) task = 3;
            if (task > 0) covered[static_cast<size_t>(std::min(task, 3) - 1)][p] = true;
        }
        return on_frame(guidance::task_map(covered, value, view, params.fovea.value_or(kDefaultFovea)));
    }
    case G::kDistractors: {
        const PixelProbe& probe = *in_.probe;
        const guidance::ViewGeometry view{probe.width, probe.height, in_.scene->camera.view_distance};
        std::vector<bool> selected;
        for (const PlanMapInput& in : inputs)
            if (is_objects(in.node)) selected = objects(in.node);
        if (selected.empty()) {
            selected.assign(in_.scene->shapes.size(), false);
            for (size_t s = 0; s < selected.size(); ++s) selected[s] = in_.scene->shapes[s].tag && in_.scene->shapes[s].tag->distractor;
        }
        std::vector<bool> detectable(probe.detected.size(), false);
        for (size_t p = 0; p < detectable.size(); ++p)
            detectable[p] = probe.detected[p] >= 0 && selected[static_cast<size_t>(probe.detected[p])];
        return on_frame(guidance::distractor_map(detectable, view, params.fovea.value_or(kDefaultFovea)));
    }
    case G::kNoise: {
        // The image so far at its pixels' mean plus and minus their standard error (the film's
        // half-buffers, buffer "noise"), both through the display tone map.
        auto it = in_.buffers.find("noise");
        if (it == in_.buffers.end() || it->second.size() != in_.preview.size()) throw std::runtime_error("noise(): no half-buffers");
        std::vector<float> high(in_.preview.size()), low(in_.preview.size());
        for (size_t i = 0; i < high.size(); ++i) {
            high[i] = in_.preview[i] + it->second[i];
            low[i] = std::max(0.0f, in_.preview[i] - it->second[i]);
        }
        return guidance::noise_map(display(high), display(low));
    }
    case G::kXmap: {
        const PixelProbe& probe = *in_.probe;
        // Fraction of the light leaving the first surface that reaches the camera through the
        // scene's homogeneous medium: exp(-sigma_t d), luminance-weighted.
        Raster m(probe.width, probe.height, 1, 1.0f);
        if (in_.scene->medium) {
            const Vec3& e = in_.scene->medium->extinction;
            double sigma = 0.2126 * e.x + 0.7152 * e.y + 0.0722 * e.z;
            for (size_t p = 0; p < m.v.size(); ++p)
                m.v[p] = sigma > 0 ? static_cast<float>(std::exp(-sigma * static_cast<double>(probe.distance[p]))) : 1.0f;
        }
        guidance::clamp01(m);
        return on_frame(m);
    }
    }
    throw std::runtime_error(fmt::format("this runtime has no guidance operator '{}'", op_name));
}

}  // namespace crex
