#include "runtime/render/executor.h"

#include <fmt/format.h>

#include <cmath>

#include "compiler/base/render_text.h"

namespace crex {

Executor::Executor(const RenderScene& scene, Film& film, const ExecutorOptions& options)
    : scene_(scene), film_(film), options_(options) {}

double Executor::importance(uint32_t pixel) const {
    double v = options_.importance ? static_cast<double>((*options_.importance)[pixel]) : options_.constant_importance;
    if (std::isnan(v)) return 0;
    return std::fmin(std::fmax(v, 0.0), 1.0);
}

void Executor::execute_rays(const RayBatch& rays, bool camera, size_t aov, ComponentStats& stats, const std::string& label) {
    auto start = std::chrono::steady_clock::now();
    auto& sink = deferring_ ? pending_ : bins_;
    for (size_t begin = 0; begin < rays.size(); begin += options_.chunk_rays) {
        size_t end = std::min(rays.size(), begin + options_.chunk_rays);
        ShadeOutput out;
        trace_and_shade(scene_, rays, begin, end, camera, options_.shade, out);
        for (size_t i = 0; i < out.contribution.size(); ++i) film_.add(aov, rays.pixel[begin + i], out.contribution[i]);
        for (size_t c = 0; c < kComponentCount; ++c) sink[c].append(out.children[c]);
        stats.rays += end - begin;
        stats.shadow_rays += out.shadow_rays;
        rays_done_ += end - begin;
        if (options_.progress) options_.progress(label, rays_done_);
    }
    stats.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Executor::run_camera_rays(const RayBatch& camera_rays) {
    execute_rays(camera_rays, true, kCameraAov, stats_.camera, "camera rays");
}

bool Executor::exec(const sched::Node& node) {
    size_t c = static_cast<size_t>(node.component);
    RayBatch& bin = bins_[c];
    RayBatch take;
    if (in_modulate_) {
        double index = node.first_index;
        for (const auto& [stride, iteration] : strides_) index += stride * static_cast<double>(iteration);
        RayBatch keep;
        for (size_t i = 0; i < bin.size(); ++i) {
            bool run = index < std::ceil(importance(bin.pixel[i]) * modulate_n_);
            (run ? take : keep).push(bin.get(i));
        }
        bin = std::move(keep);
    } else {
        std::swap(take, bin);
    }
    if (take.empty()) return false;
    ComponentStats& stats = stats_.components[c];
    ++stats.executions;
    stats_.steps.push_back({node.component, take.size()});
    execute_rays(take, false, aov_of(node.component), stats, std::string(1, component_letter(node.component)));
    return true;
}

bool Executor::run(const sched::Node& node) {
    using sched::Op;
    switch (node.op) {
    case Op::kExec: return exec(node);
    case Op::kSeq: {
        bool work = false;
        for (const auto& child : node.children) work |= run(child);
        return work;
    }
    case Op::kDefer:
    case Op::kBudgeted: {
        bool owns = node.op == Op::kDefer || node.owns_deferral;
        if (!owns || deferring_) {
            bool work = false;
            for (const auto& child : node.children) work |= run(child);
            return work;
        }
        deferring_ = true;
        bool work = false;
        for (const auto& child : node.children) work |= run(child);
        deferring_ = false;
        for (size_t c = 0; c < kComponentCount; ++c) {
            bins_[c].append(pending_[c]);
            pending_[c].clear();
        }
        return work;
    }
    case Op::kModulate: {
        bool saved_in = in_modulate_;
        double saved_n = modulate_n_;
        auto saved_strides = std::move(strides_);
        in_modulate_ = true;
        modulate_n_ = node.occurrences;
        strides_.clear();
        bool work = false;
        for (const auto& child : node.children) work |= run(child);
        in_modulate_ = saved_in;
        modulate_n_ = saved_n;
        strides_ = std::move(saved_strides);
        return work;
    }
    case Op::kRepeat: {
        bool work = false;
        bool numbered = in_modulate_ && node.stride > 0;
        if (numbered) strides_.push_back({node.stride, 0});
        for (uint64_t k = 0; k < node.count; ++k) {
            if (numbered) strides_.back().second = k;
            work |= run(node.children.front());
        }
        if (numbered) strides_.pop_back();
        return work;
    }
    case Op::kRepeatUntilEmpty: {
        bool any = false;
        for (uint32_t k = 0;; ++k) {
            if (k >= node.cap) {
                warnings_.push_back(fmt::format("{}: warning[W401]: '*' stopped after {} iterations (the cap) with work left",
                                                format_location(node.span), node.cap));
                break;
            }
            bool work = run(node.children.front());
            any |= work;
            if (!work) break;
        }
        return any;
    }
    }
    return false;
}

}  // namespace crex
