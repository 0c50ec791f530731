#include "runtime/pipeline/run_pipeline.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "runtime/pipeline/guidance_graph.h"
#include "runtime/pipeline/pixel_probe.h"
#include "runtime/pipeline/svt.h"
#include "runtime/base/sampling.h"

namespace crex {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

uint64_t total_rays(const ExecutorStats& s) {
    uint64_t n = s.camera.rays;
    for (const auto& c : s.components) n += c.rays;
    return n;
}

bool needs_probe(const PipelinePlan& plan) {
    for (const auto& m : plan.maps)
        if (m.op && pipeline::signature(*m.op).needs_scene) return true;
    return false;
}

std::vector<float> map_values(const guidance::Raster& r, size_t pixels) {
    if (r.channels != 1 || r.pixels() != pixels) throw std::runtime_error("a map does not have the image's size");
    return r.v;
}

}  // namespace

bool has_guidance(const PipelinePlan& plan) {
    return !plan.maps.empty() || !plan.variables.empty();
}

std::vector<float> PipelineRunResult::image() const {
    std::vector<float> rgb = render.image();
    if (subsample) subsample->fill(rgb);
    return rgb;
}

std::vector<float> PipelineRunResult::aov_image(size_t aov) const {
    std::vector<float> rgb = render.film.aov_image(aov);
    if (subsample) subsample->fill(rgb);
    return rgb;
}

PipelineRunResult run_pipeline(const Scene& scene, const PipelinePlan& plan, const PipelineRunOptions& options) {
    auto t_setup = Clock::now();
    RenderScene rs(scene);
    const int w = options.width, h = options.height;
    PipelineRunResult out(w, h);
    out.render.setup_seconds = seconds_since(t_setup);
    Film& film = out.render.film;
    const size_t pixels = film.pixel_count();

    // One clock for both stages: a budget counts from the first camera ray (spec §7).
    const auto t0 = Clock::now();
    ExecutorOptions base = options.executor;
    CheckpointRecorder* rec = options.recorder;
    const Executor* main_ptr = nullptr;
    const Executor* added_ptr = nullptr;
    const RayBatch* d_bins[2] = {nullptr, nullptr};
    auto rays_so_far = [&] { return (main_ptr ? main_ptr->rays_done() : 0) + (added_ptr ? added_ptr->rays_done() : 0); };
    auto snapshot = [&] {
        std::vector<double> amb(3 * pixels, 0.0);
        for (const RayBatch* d : d_bins)
            if (d) {
                auto a = ambient_buffer(*d, options.ambient, pixels);
                for (size_t i = 0; i < a.size(); ++i) amb[i] += a[i];
            }
        std::vector<float> rgb = film.composite(&amb);
        if (out.subsample) out.subsample->fill(rgb);
        return rgb;
    };
    if (rec) {
        rec->start();
        base.clock = [rec] { return rec->now(); };
        base.checkpoint = [&](const std::string& what, bool boundary) { rec->event(what, boundary, rays_so_far(), snapshot); };
    } else if (!base.clock) {
        base.clock = [t0] { return seconds_since(t0); };
    }
    auto stage_end = [&](const std::string& what, const std::string& next) {
        if (!rec) return;
        rec->event(what, true, rays_so_far(), snapshot, true);
        rec->set_stage(next);
    };

    // The irradiance cache: the preview at the base accuracy (ic_radius where its map is 0).
    std::optional<IrradianceCache> cache;
    std::vector<IcAnswer> preview_answers;
    double base_aa = options.irradiance_cache ? options.irradiance_cache->accuracy : 0;
    if (options.irradiance_cache) {
        IcSettings ics = *options.irradiance_cache;
        for (const PlanVariable& v : plan.variables)
            if (v.variable == pipeline::SelectiveVariable::kIcRadius) {
                base_aa = v.from;
                ics.accuracy = v.from;
                ics.max_accuracy = std::max({v.from, v.to, ics.accuracy});
            }
        cache.emplace(rs, ics);
        for (const auto& r : options.ic_records) cache->insert(r);
        base.shade.ic_queries = true;
        base.irradiance = executor_hook(*cache, base_aa, nullptr, nullptr, &preview_answers);
    }

    // 1. Pre-selective.
    Executor main(rs, film, base);
    main_ptr = &main;
    d_bins[0] = &main.bins()[static_cast<size_t>(Component::kD)];
    CameraRays camera(scene.camera, w, h, rs.embree->origin_offset());
    const uint32_t s0 = options.preview_spp;
    {
        RayBatch rays;
        for (uint32_t p = 0; p < pixels; ++p) {
            append_camera_rays(camera, options.seed, w, p, 0, s0, rays, options.filter);
            film.add_samples(p, s0);
        }
        main.run_camera_rays(rays);
    }
    main.run(plan.program.preselective);
    const RayBatch& d_bin = main.bins()[static_cast<size_t>(Component::kD)];
    std::vector<double> ambient = ambient_buffer(d_bin, options.ambient, pixels);
    out.preview = film.composite(&ambient);
    out.preview_seconds = seconds_since(t0);
    out.preview_rays = total_rays(main.stats());
    if (cache) out.ic_preview_records = cache->records().size();
    stage_end("end of the pre-selective stage", "guidance");

    // 2. Guidance.
    auto t_guidance = Clock::now();
    GuidanceInputs in;
    in.width = w, in.height = h;
    in.preview = out.preview;
    in.scene = &scene;
    std::vector<float> camera_aov = film.aov_image(kCameraAov), emission = film.emission_image();
    for (size_t i = 0; i < camera_aov.size(); ++i) camera_aov[i] = std::max(0.0f, camera_aov[i] - emission[i]);
    in.buffers["direct"] = std::move(camera_aov);
    in.buffers["emission"] = std::move(emission);
    {
        std::vector<float> a(3 * pixels, 0.0f);
        for (uint32_t p = 0; p < pixels; ++p)
            for (size_t c = 0; c < 3; ++c)
                a[3 * p + c] = film.samples(p) ? static_cast<float>(ambient[3 * p + c] / film.samples(p)) : 0.0f;
        in.buffers["ambient"] = std::move(a);
    }
    for (size_t c = 0; c < kComponentCount; ++c)
        in.buffers[std::string(1, kComponentTable[c].letter)] = film.aov_image(aov_of(static_cast<Component>(c)));
    PixelProbe probe;
    if (needs_probe(plan)) {
        probe = probe_pixels(rs, w, h);
        in.probe = &probe;
    }
    GuidanceGraph graph(plan, std::move(in));
    for (const auto& m : plan.maps)
        if (!m.defines.empty()) out.maps.push_back({m.defines, graph.map(m.id)});

    // The svt.
    ShadeParams shade = base.shade;
    std::vector<double> spp(pixels, s0);
    if (plan.settings.selective_spp) std::fill(spp.begin(), spp.end(), std::max<double>(s0, *plan.settings.selective_spp));
    std::vector<uint16_t> shadow_rays;
    std::vector<float> specular_threshold;
    std::vector<float> ic_accuracy, ic_priority;
    for (const PlanVariable& var : plan.variables) {
        const std::string& by = var.map;
        std::vector<float> m = map_values(graph.map(by), pixels);
        if (by.rfind("map.", 0) != 0) out.maps.push_back({by, graph.map(by)});
        // One case per pipeline::SelectiveVariable, no default (-Werror=switch).
        using V = pipeline::SelectiveVariable;
        switch (var.variable) {
        case V::kSpp:
            spp = variable_values(var.from, var.to, var.modulation, m, true);
            break;
        case V::kShadowRays: {
            auto v = variable_values(var.from, var.to, var.modulation, m, true);
            shadow_rays.resize(pixels);
            uint32_t mx = 1;
            for (size_t p = 0; p < pixels; ++p) {
                shadow_rays[p] = static_cast<uint16_t>(std::clamp(v[p], 1.0, 1024.0));
                mx = std::max<uint32_t>(mx, shadow_rays[p]);
            }
            shade.shadow_rays = mx;
            shade.shadow_rays_per_pixel = &shadow_rays;
            break;
        }
        case V::kSpecularThreshold: {
            auto v = variable_values(var.from, var.to, var.modulation, m, false);
            specular_threshold.assign(v.begin(), v.end());
            shade.specular_threshold_per_pixel = &specular_threshold;
            break;
        }
        case V::kSubsample:
            out.subsample.emplace(w, h, variable_values(var.from, var.to, var.modulation, m, true));
            break;
        case V::kIcRadius: {
            if (!cache) {
                out.notes.push_back("ic_radius is not executed: the render has no irradiance cache");
                continue;
            }
            auto v = variable_values(var.from, var.to, var.modulation, m, false);
            ic_accuracy.assign(v.begin(), v.end());
            ic_priority = m;
            break;
        }
        case V::kMediaSamples:
            out.notes.push_back("media_samples is not executed: the renderer has no participating media yet");
            break;
        }
    }
    std::vector<float> modulation;
    const std::string& modulation_map = plan.modulation_map;
    if (!modulation_map.empty()) {
        modulation = map_values(graph.map(modulation_map), pixels);
        if (modulation_map.rfind("map.", 0) != 0) out.maps.push_back({modulation_map, graph.map(modulation_map)});
    }
    out.guidance_seconds = seconds_since(t_guidance);
    stage_end("end of guidance", "selective");

    // 3. Selective: new camera samples continue each pixel's sequence where the preview stopped.
    auto t_selective = Clock::now();
    ExecutorOptions selective = base;
    selective.shade = shade;
    if (cache) {
        // The preview's D samples of pixels that now ask for a finer accuracy are answered
        // again, important pixels first; the old answer's light is taken back out of the film.
        if (!ic_accuracy.empty()) {
            std::vector<IcQuery> again;
            std::vector<const IcAnswer*> from;
            for (const auto& a : preview_answers) {
                uint32_t p = a.query.pixel;
                if (!(ic_accuracy[p] < a.accuracy - 1e-9)) continue;
                again.push_back({a.query.origin, normalize_or_zero(a.query.direction), ic_accuracy[p], ic_priority[p], a.query.path});
                from.push_back(&a);
            }
            size_t before = cache->records().size();
            std::vector<Vec3> e;
            cache->irradiance(again, 0, e);
            for (size_t i = 0; i < again.size(); ++i) {
                Vec3 delta = from[i]->query.beta * (e[i] - from[i]->irradiance) / kPi;
                if (is_finite(delta)) film.add(aov_of(Component::kD), from[i]->query.pixel, delta);
            }
            out.ic_reprocessed = again.size();
            out.ic_selective_records = cache->records().size() - before;
        }
        selective.irradiance = executor_hook(*cache, base_aa, ic_accuracy.empty() ? nullptr : &ic_accuracy,
                                             ic_priority.empty() ? nullptr : &ic_priority);
        main.set_irradiance(selective.irradiance);
    }
    {
        RayBatch rays;
        for (uint32_t p = 0; p < pixels; ++p) {
            if (out.subsample && !out.subsample->rendered(p)) continue;
            uint32_t target = static_cast<uint32_t>(std::clamp(spp[p], 1.0, double(1u << 20)));
            if (target <= s0) continue;
            append_camera_rays(camera, options.seed, w, p, s0, target - s0, rays, options.filter);
            film.add_samples(p, target - s0);
        }
        if (!rays.empty()) {
            Executor added(rs, film, selective);
            added_ptr = &added;
            d_bins[1] = &added.bins()[static_cast<size_t>(Component::kD)];
            added.run_camera_rays(rays);
            added.run(plan.program.preselective);
            main.adopt(added);
            added_ptr = nullptr;
            d_bins[1] = nullptr;
        }
    }
    main.set_shade_params(shade);
    if (!modulation.empty()) main.set_importance(&modulation);
    main.run(plan.program.selective);
    main.set_importance(nullptr);
    out.selective_seconds = seconds_since(t_selective);

    RenderResult& r = out.render;
    if (cache) {
        r.ic_records = cache->records();
        r.ic_stats = cache->stats();
        out.ic_selective_records = cache->records().size() - out.ic_preview_records;
    }
    r.ambient = ambient_buffer(main.bins()[static_cast<size_t>(Component::kD)], options.ambient, pixels);
    for (size_t c = 0; c < kComponentCount; ++c) r.rays_left[c] = main.bins()[c].size();
    r.stats = main.stats();
    r.warnings = main.warnings();
    r.render_seconds = seconds_since(t0);
    out.selective_rays = total_rays(r.stats) - out.preview_rays;
    stage_end("end of render", "end");
    return out;
}

}  // namespace crex
