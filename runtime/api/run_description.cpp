#include "runtime/api/run_description.h"

#include <fmt/format.h>

#include "compiler/pipeline/settings_table.h"
#include "compiler/sched/print.h"

namespace crex {

std::string pixel_settings_text(const RunSettings& s) {
    const ShadeParams& shade = s.executor.shade;
    const char* uniform = s.uniform == UniformQuality::kMax ? "max" : s.uniform == UniformQuality::kMin ? "min" : "off";
    return fmt::format("size {}x{}, spp {}, filter {}, shadow-rays {}, media-samples {}, lw {:g}, max-depth {}, roulette {}, clamp {:g}, "
                       "ambient {}, importance {:g}, rounds {}, uniform {}",
                       s.width, s.height, s.spp, s.filter == PixelFilter::kGaussian ? "gaussian" : "box", shade.shadow_rays,
                       shade.media_samples, shade.weight_limit, shade.max_depth, shade.roulette ? "on" : "off", s.executor.clamp_indirect,
                       s.ambient_auto ? std::string("auto") : fmt::format("{:g}", s.ambient.x), s.executor.constant_importance,
                       s.rounds, uniform);
}

std::string describe_run(const RunInputs& in, const ResolvedRun& run, int threads, const std::string& prefix) {
    const RunSettings& s = run.settings;
    std::string out;
    if (in.scene && in.scene->scene) {
        const Scene& scene = *in.scene->scene;
        out += prefix + fmt::format("scene: {}{}: {} shapes, {} materials, {} distant lights{}; read in {:.3f} s\n", in.scene_spec,
                           scene.source == in.scene_spec ? "" : " (" + scene.source + ")", scene.shapes.size(), scene.materials.size(), scene.distant_lights.size(),
                           scene.medium ? ", a medium" : "", in.load_seconds);
    }
    if (in.plan.staged) out += prefix + fmt::format("plan: pipeline {}, crex {}\n", in.plan.name, sched::to_crex(in.plan.program));
    else out += prefix + fmt::format("plan: crex {}\n", sched::to_crex(in.plan.program));
    out += prefix + fmt::format("pixels: {}, seed {}\n", pixel_settings_text(s), s.seed);
    if (const auto& ic = s.irradiance_cache)
        out += prefix + fmt::format("irradiance cache: aa {:g}, ad {}, ab {}, ar {:g}, caustic photons {}{}\n", ic->accuracy, ic->divisions,
                           ic->bounces, ic->resolution, ic->caustic_photons, s.ic_file.empty() ? "" : ", file " + s.ic_file);
    else out += prefix + "irradiance cache: off\n";
    if (run.budget_seconds > 0)
        out += prefix + fmt::format("budget: {:.3f} s, policy {}{}\n", run.budget_seconds,
                           s.policy ? std::string(pipeline::name_of(*s.policy)) : std::string("the plan's"),
                           run.predicted ? ", costs predicted from " + run.predicted->path : "");
    else out += prefix + "budget: none (everything the plan asks for is rendered)\n";
    const LimitOrigins& at = run.limits_set_at;
    for (const auto& [name, where] : {std::pair{"max-depth", &at.max_depth}, std::pair{"lw", &at.lw}, std::pair{"ab", &at.ab}})
        if (!where->empty()) out += prefix + fmt::format("limits: {} set by the plan at {}\n", name, *where);
    out += prefix + fmt::format("threads: {}; memory: passes sized for {} MiB{}\n", threads > 0 ? std::to_string(threads) : "all cores",
                       s.max_memory >> 20, s.pass_samples ? fmt::format(", at most {} samples a pass", s.pass_samples) : "");
    return out;
}

}  // namespace crex
