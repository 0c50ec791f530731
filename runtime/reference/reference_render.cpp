#include "runtime/reference/reference_render.h"

#include <fmt/format.h>

#include "runtime/io/image_io.h"
#include "runtime/reference/windowed_image.h"
#include "stdlib/guidance/operators.h"

namespace crex {

RenderedPixels render_reference_pixels(const Scene& scene, const sched::Program& program, const ReferencePixels& s) {
    RunSettings ro;
    ro.width = s.width, ro.height = s.height, ro.spp = s.spp, ro.first_sample = s.first_sample, ro.seed = s.seed;
    ro.executor.shade.weight_limit = s.lw;
    ro.executor.shade.max_depth = s.max_depth;
    const bool windowed = !s.windows.empty();
    if (windowed) ro.windows = s.windows;
    ProgressFunction observer(s.progress);
    RunResult r = render(scene, program, ro, observer);
    RenderedPixels out;
    out.seconds = r.render_seconds;
    out.rgb = windowed ? WindowAtlas(s.windows).pack(r.image(), s.width) : r.image();
    return out;
}

FrameContext render_frame_context(const Scene& scene, const sched::Program& program, int width, int height, uint32_t spp, uint64_t seed,
                                  const std::function<void(const RunProgress&)>& progress) {
    RunSettings ro;
    ro.width = width, ro.height = height, ro.spp = spp, ro.seed = seed;
    ro.irradiance_cache = IcSettings{};
    ro.irradiance_cache->seed = seed;
    ProgressFunction observer(progress);
    RunResult r = render(scene, program, ro, observer);
    FrameContext c;
    c.width = width, c.height = height;
    c.rgb = r.image();
    c.exposure = display_exposure(c.rgb);
    guidance::Raster display(width, height, 3);
    display.v = to_display(c.rgb, c.exposure);
    c.saliency = guidance::saliency(display).v;
    c.seconds = r.render_seconds;
    c.how = fmt::format("{} spp through the irradiance cache (aa {:g}), seed {}", spp, IcSettings{}.accuracy, seed);
    return c;
}

}  // namespace crex
