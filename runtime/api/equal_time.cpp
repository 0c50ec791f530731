#include "runtime/api/equal_time.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "base/check.h"
#include "compiler/compiler.h"
#include "runtime/api/run_inputs.h"
#include "runtime/io/image_io.h"
#include "stdlib/guidance/operators.h"

namespace crex {

namespace {

// A ceiling, not a target: the budget ends the render long before (passes are sized by memory).
constexpr uint32_t kUniformSppCeiling = 1u << 16;

}  // namespace

EqualTimeRun render_uniform_in_equal_time(const Scene& scene, const RunSettings& pipeline, double seconds) {
    CREX_CHECK(seconds > 0);
    EqualTimeRun out;
    out.crex = kDefaultCrex;
    DiagnosticSink sink;
    const SourceFile source("<equal-time>", out.crex);
    const std::optional<sched::Program> program = compile_crex(source, sink).program;
    CREX_CHECK(program.has_value());
    PipelinePlan plan;  // unnamed and unstaged: a plain crex, spent in progressive passes
    plan.program = *program;

    // The pipeline's picture and limits; none of its selectivity.
    RunSettings s;
    s.width = pipeline.width, s.height = pipeline.height;
    s.spp = kUniformSppCeiling;
    s.seed = pipeline.seed;
    s.filter = pipeline.filter;
    s.executor.shade = pipeline.executor.shade;
    s.executor.clamp_indirect = pipeline.executor.clamp_indirect;
    s.executor.budget_seconds = seconds;
    s.irradiance_cache = pipeline.irradiance_cache;  // the same cache settings, its file neither read nor written
    s.max_memory = pipeline.max_memory;
    s.pass_samples = pipeline.pass_samples;
    s.texture_filter_width = pipeline.texture_filter_width;
    s.caustic_photons = pipeline.caustic_photons;
    out.irradiance_cache = s.irradiance_cache.has_value();
    out.budget_seconds = seconds;

    const RunResult r = run_plan(scene, plan, s);
    out.render_seconds = r.render_seconds;
    out.image = r.image();
    const size_t pixels = static_cast<size_t>(s.width) * static_cast<size_t>(s.height);
    uint64_t total = 0;
    out.min_spp = std::numeric_limits<uint32_t>::max();
    for (uint32_t p = 0; p < pixels; ++p) {
        const uint32_t n = r.film.samples(p);
        total += n;
        out.min_spp = std::min(out.min_spp, n);
        out.max_spp = std::max(out.max_spp, n);
    }
    if (pixels == 0) out.min_spp = 0;
    out.mean_spp = pixels ? static_cast<double>(total) / static_cast<double>(pixels) : 0;
    return out;
}

std::vector<float> saliency_weights(const metrics::Image& display_rgb) {
    guidance::Raster rgb(display_rgb.width, display_rgb.height, 3);
    rgb.v = display_rgb.rgb;
    std::vector<float> weights = guidance::saliency(rgb).v;
    // A featureless image draws the eye nowhere in particular: every pixel counts alike.
    if (std::none_of(weights.begin(), weights.end(), [](float w) { return w > 0; })) std::fill(weights.begin(), weights.end(), 1.0f);
    return weights;
}

std::vector<float> equal_time_attention(const PipelinePlan& plan, const std::vector<std::pair<std::string, guidance::Raster>>& maps,
                                        const metrics::Image& reference, const metrics::DisplayView& view, std::string& attention) {
    for (const PlanMap& m : plan.maps) {
        if (m.defines.empty() || m.op != pipeline::GuidanceOperator::kTaskMap) continue;
        for (const auto& [name, raster] : maps)
            if (name == m.defines && raster.channels == 1 && raster.pixels() == static_cast<size_t>(reference.width) * reference.height &&
                std::any_of(raster.v.begin(), raster.v.end(), [](float v) { return v > 0; })) {
                attention = fmt::format("the pipeline's task map '{}'", name);
                return raster.v;
            }
    }
    attention = "the reference's saliency";
    return saliency_weights(metrics::display_view(reference, view));
}

EqualTimeScore score_equal_time(const std::vector<float>& pipeline_image, const EqualTimeRun& uniform, const metrics::Image& reference,
                                const std::vector<float>& weights, std::string attention) {
    EqualTimeScore score;
    score.attention = std::move(attention);
    score.view = {true, display_exposure(reference.rgb)};
    metrics::MetricChoice choice;
    choice.rmse = choice.flip = choice.flip_map = true;
    score.pipeline = metrics::compare_images({reference.width, reference.height, pipeline_image}, reference, score.view, choice, &weights);
    score.uniform = metrics::compare_images({reference.width, reference.height, uniform.image}, reference, score.view, choice, &weights);
    return score;
}

nlohmann::json equal_time_json(const EqualTimeRun& uniform, const EqualTimeScore& score) {
    auto figures = [](const metrics::ImageComparison& c) {
        nlohmann::json j;
        j["flip"] = c.flip.value_or(0);
        j["aflip"] = c.aflip ? nlohmann::json(*c.aflip) : nlohmann::json(nullptr);
        j["rmse"] = c.rmse.value_or(0);
        return j;
    };
    nlohmann::json j;
    j["seconds"] = uniform.budget_seconds;
    j["attention"] = score.attention;
    j["pipeline"] = figures(score.pipeline);
    j["uniform"] = figures(score.uniform);
    j["uniform"]["crex"] = uniform.crex;
    j["uniform"]["irradiance_cache"] = uniform.irradiance_cache;
    j["uniform"]["render_seconds"] = uniform.render_seconds;
    j["uniform"]["spp"] = {{"mean", uniform.mean_spp}, {"min", uniform.min_spp}, {"max", uniform.max_spp}};
    return j;
}

void print_equal_time(const nlohmann::json& j, std::ostream& out) {
    const auto& p = j["pipeline"];
    const auto& u = j["uniform"];
    auto aflip = [](const nlohmann::json& x) { return x["aflip"].is_null() ? std::string("n/a") : fmt::format("{:.4f}", x["aflip"].get<double>()); };
    out << fmt::format("equal time ({:.3f} s), against the reference; aFLIP weighted by {}\n", j["seconds"].get<double>(),
                       j["attention"].get<std::string>());
    out << fmt::format("  pipeline  FLIP {:.4f}  aFLIP {}\n", p["flip"].get<double>(), aflip(p));
    out << fmt::format("  uniform   FLIP {:.4f}  aFLIP {}   (crex {}{}, {:.1f} spp on average, {:.3f} s)\n", u["flip"].get<double>(), aflip(u),
                       u["crex"].get<std::string>(), u["irradiance_cache"].get<bool>() ? " through the cache" : "",
                       u["spp"]["mean"].get<double>(), u["render_seconds"].get<double>());
}

}  // namespace crex
