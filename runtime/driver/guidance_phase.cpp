#include "runtime/driver/guidance_phase.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "base/check.h"
#include "runtime/driver/run_result.h"
#include "runtime/driver/run_settings.h"
#include "runtime/pipeline/guidance_graph.h"
#include "runtime/pipeline/svt.h"

namespace crex {

uint16_t ic_rays_step(double rays) {
    return static_cast<uint16_t>(1u << static_cast<int>(std::clamp(std::round(std::log2(std::max(rays, 1.0))), 4.0, 15.0)));
}

namespace {

bool needs_probe(const PipelinePlan& plan) {
    for (const PlanMap& m : plan.maps)
        if (m.op && pipeline::signature(*m.op).needs_scene) return true;
    return false;
}

std::vector<float> map_values(const guidance::Raster& r, size_t pixels) {
    // Every operator makes one-channel maps of the image's size.
    CREX_CHECK_EQ(r.channels, 1);
    CREX_CHECK_EQ(r.pixels(), pixels);
    return r.v;
}

// A per-pixel count of rays or samples (1..1024) from a variable's values; returns the largest,
// which sizes the shading buffers.
uint32_t per_pixel_counts(const std::vector<double>& values, std::vector<uint16_t>& counts) {
    counts.resize(values.size());
    uint32_t mx = 1;
    for (size_t p = 0; p < values.size(); ++p) {
        counts[p] = static_cast<uint16_t>(std::clamp(values[p], 1.0, 1024.0));
        mx = std::max<uint32_t>(mx, counts[p]);
    }
    return mx;
}

// Has any pixel an even and an odd sample (the two halves noise() compares)?
bool two_samples_somewhere(const Film& film) {
    for (uint32_t p = 0; p < film.pixel_count(); ++p)
        if (film.samples(p) >= 2) return true;
    return false;
}

}  // namespace

std::set<std::string> guidance_reads(const PipelinePlan& plan) {
    std::set<std::string> read;
    for (const PlanBuffer& b : plan.buffers) read.insert(b.buffer);
    for (const PlanMap& m : plan.maps)
        if (m.op == pipeline::GuidanceOperator::kNoise) read.insert("noise");
    return read;
}

SelectiveSetup run_guidance(const GuidanceContext& ctx, const std::vector<float>& image, const std::vector<double>& stand_ins,
                            RunResult& out, std::optional<PixelProbe>& surfaces, uint32_t grid_stride) {
    const RunSettings& s = ctx.settings;
    const PipelinePlan& plan = ctx.plan;
    const int w = s.width, h = s.height;
    const size_t pixels = out.film.pixel_count();
    const Film& film = out.film;
    const uint32_t s0 = s.spp;
    SelectiveSetup sel;
    sel.shade = s.executor.shade;
    // With a cache, D hits stay irradiance queries in the selective stage too. (They did not:
    // every selective D sample was path traced, so a cached pipeline's gold had the fireflies
    // of uniform path tracing at twice the cost; Cornell 128x128 prog_dis_all --uniform max,
    // FLIP 0.122 against 0.080 for crex run --ic with the same settings.)
    sel.shade.ic_queries = ctx.has_cache;
    sel.spp_end.assign(pixels, s0);
    if (plan.settings.selective_spp) std::fill(sel.spp_end.begin(), sel.spp_end.end(), std::max(s0, *plan.settings.selective_spp));

    // The maps: computed by the guidance graph, or constant under --uniform.
    std::optional<GuidanceGrid> grid;  // before the graph, which points at them
    std::optional<PixelProbe> grid_probe;
    std::optional<GuidanceGraph> graph;
    std::optional<guidance::Raster> constant;
    if (s.uniform != UniformQuality::kOff) {
        guidance::Raster r;
        r.width = w, r.height = h, r.channels = 1;
        r.v.assign(pixels, s.uniform == UniformQuality::kMax ? 1.0f : 0.0f);
        constant = std::move(r);
    } else {
        GuidanceInputs in;
        in.width = w, in.height = h;
        in.preview = image;
        in.scene = &ctx.scene;
        const std::set<std::string> read = guidance_reads(plan);
        if (read.count("noise")) in.buffers["noise"] = film.noise_image();
        if (read.count("direct") || read.count("emission")) {
            std::vector<float> camera_aov = film.aov_image(kCameraAov), emission = film.emission_image();
            for (size_t i = 0; i < camera_aov.size(); ++i) camera_aov[i] = std::max(0.0f, camera_aov[i] - emission[i]);
            if (read.count("direct")) in.buffers["direct"] = std::move(camera_aov);
            if (read.count("emission")) in.buffers["emission"] = std::move(emission);
        }
        if (read.count("ambient")) {
            std::vector<float> a(3 * pixels, 0.0f);
            for (uint32_t p = 0; p < pixels && !stand_ins.empty(); ++p)
                for (size_t c = 0; c < 3; ++c)
                    a[3 * p + c] = film.samples(p) ? static_cast<float>(stand_ins[3 * p + c] / film.samples(p)) : 0.0f;
            in.buffers["ambient"] = std::move(a);
        }
        for (size_t c = 0; c < kComponentCount; ++c) {
            std::string letter(1, kComponentTable[c].letter);
            if (read.count(letter)) in.buffers[letter] = film.aov_image(aov_of(static_cast<Component>(c)));
        }
        // A strided preview's pixels without samples: interpolated as the preview image is.
        if (out.preview_grid && !in.buffers.empty()) {
            const SubsampleGrid::Fill fill = out.preview_grid->unsampled_fill(out.sampled_pixels());
            for (auto& [name, buffer] : in.buffers) out.fill_unsampled_preview(buffer, &fill);
        }
        if (needs_probe(plan) && grid_stride > 1) {  // after a strided preview: its grid's pixels
            grid.emplace(w, h, grid_stride);
            grid_probe = probe_pixels(ctx.render_scene, w, h, grid->columns(), grid->rows());
            in.probe = &*grid_probe;
            in.grid = &*grid;
        } else if (needs_probe(plan)) {  // the camera does not move between rounds: probed once a run
            if (!surfaces) surfaces = probe_pixels(ctx.render_scene, w, h);
            in.probe = &*surfaces;
        }
        graph.emplace(plan, std::move(in));
        out.maps.clear();  // a later round's maps replace the earlier ones
        for (const PlanMap& m : plan.maps)
            if (!m.defines.empty()) {
                const guidance::Raster& r = graph->map(m.id);
                out.maps.push_back({m.defines, r});
                if (std::all_of(r.v.begin(), r.v.end(), [](float v) { return !(v > 0); }))
                    out.notes.push_back(fmt::format("map '{}' is 0 everywhere: what it drives stays at its base value{}", m.name,
                                                     m.op == pipeline::GuidanceOperator::kNoise && !two_samples_somewhere(film)
                                                         ? " (noise() compares a pixel's even and odd samples, and no pixel has two "
                                                           "yet: a budget cut the preview, or its spp is 1)"
                                                         : ""));
            }
    }
    auto map_of = [&](const std::string& id) -> const guidance::Raster& {
        if (constant) return *constant;
        const guidance::Raster& r = graph->map(id);
        if (id.rfind("map.", 0) != 0) {  // an inline map (`by edges(direct)`): shown as the user wrote it
            std::string shown = id;
            for (const PlanMap& m : plan.maps)
                if (m.id == id && !m.name.empty()) shown = m.name;
            bool seen = false;
            for (const auto& [name, raster] : out.maps) seen |= name == shown;
            if (!seen) out.maps.push_back({shown, r});
        }
        return r;
    };

    for (const PlanVariable& var : plan.variables) {
        std::vector<float> m = map_values(map_of(var.map), pixels);
        // One case per pipeline::SelectiveVariable, no default (-Werror=switch): a variable the
        // compiler knows and the runtime does not bind does not compile.
        using V = pipeline::SelectiveVariable;
        switch (var.variable) {
        case V::kSpp: {
            auto v = variable_values(var.from, var.to, var.modulation, m, true);
            for (size_t p = 0; p < pixels; ++p) sel.spp_end[p] = static_cast<uint32_t>(std::clamp(v[p], 1.0, double(1u << 20)));
            break;
        }
        case V::kShadowRays: {
            sel.shade.shadow_rays = per_pixel_counts(variable_values(var.from, var.to, var.modulation, m, true), sel.shadow_rays);
            break;
        }
        case V::kSpecularThreshold: {
            auto v = variable_values(var.from, var.to, var.modulation, m, false);
            sel.specular_threshold.assign(v.begin(), v.end());
            break;
        }
        case V::kSubsample:
            if (!var.component) {
                out.subsample.emplace(w, h, variable_values(var.from, var.to, var.modulation, m, true));
                break;
            }
            if (!out.component_subsample.has_surfaces()) {  // capict: which corners see a pixel's surface
                if (!surfaces) surfaces = probe_pixels(ctx.render_scene, w, h);
                out.component_subsample.set_surfaces(*surfaces);
            }
            out.component_subsample.build(*var.component, w, h, variable_values(var.from, var.to, var.modulation, m, true), film);
            break;
        case V::kIcRadius: {
            if (!ctx.has_cache) {
                out.notes.push_back("ic_radius is not executed: the render has no irradiance cache");
                break;
            }
            auto v = variable_values(var.from, var.to, var.modulation, m, false);
            sel.ic_accuracy.assign(v.begin(), v.end());
            sel.ic_priority = m;
            break;
        }
        case V::kIcRays: {
            if (!ctx.has_cache) {
                out.notes.push_back("ic_rays is not executed: the render has no irradiance cache");
                break;
            }
            auto v = variable_values(var.from, var.to, var.modulation, m, false);
            sel.ic_divisions.resize(pixels);
            for (size_t p = 0; p < pixels; ++p) sel.ic_divisions[p] = ic_rays_step(v[p]);
            if (sel.ic_priority.empty()) sel.ic_priority = m;  // quieter pixels' records first
            break;
        }
        case V::kMediaSamples: {
            if (!ctx.render_scene.medium) {
                out.notes.push_back("media_samples is not executed: the scene has no participating medium");
                break;
            }
            sel.shade.media_samples = per_pixel_counts(variable_values(var.from, var.to, var.modulation, m, true), sel.media_samples);
            break;
        }
        }
    }
    if (!plan.modulation_map.empty()) sel.modulation = map_values(map_of(plan.modulation_map), pixels);
    if (out.subsample)
        for (size_t p = 0; p < pixels; ++p)
            if (!out.subsample->rendered(static_cast<uint32_t>(p))) sel.spp_end[p] = 0;
    return sel;
}

}  // namespace crex
