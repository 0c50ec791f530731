#include "runtime/reference/reference_render.h"

#include <fmt/format.h>

#include <algorithm>
#include <climits>

#include "runtime/io/image_io.h"
#include "runtime/reference/windowed_image.h"
#include "stdlib/guidance/operators.h"

namespace crex {
namespace {

// ReferencePixels' progress and stop as a run's observer.
class ReferenceObserver final : public RunObserver {
public:
    explicit ReferenceObserver(const ReferencePixels& s) : s_(s) {}
    void progress(const RunProgress& p) override {
        if (s_.progress) s_.progress(p);
    }
    bool stop_requested() override { return s_.stop && s_.stop(); }

private:
    const ReferencePixels& s_;
};

}  // namespace

RenderedPixels render_reference_pixels(const Scene& scene, const sched::Program& program, const ReferencePixels& s) {
    RunSettings ro;
    ro.width = s.width, ro.height = s.height, ro.spp = s.spp, ro.first_sample = s.first_sample, ro.seed = s.seed;
    ro.executor.shade.weight_limit = s.lw;
    ro.executor.shade.max_depth = s.max_depth;
    const bool windowed = !s.windows.empty();
    if (windowed) ro.windows = s.windows;
    ReferenceObserver observer(s);
    RunResult r = render(scene, program, ro, observer);
    RenderedPixels out;
    out.seconds = r.render_seconds;
    out.rgb = windowed ? WindowAtlas(s.windows).pack(r.image(), s.width) : r.image();
    out.stopped = r.stopped;
    out.spp = s.spp;
    if (r.stopped) {  // a reference is one count for all its pixels: what every rendered pixel got
        uint32_t least = UINT32_MAX, most = 0;
        auto count = [&](int x, int y) {
            const uint32_t n = r.film.samples(static_cast<uint32_t>(y) * static_cast<uint32_t>(s.width) + static_cast<uint32_t>(x));
            least = std::min(least, n), most = std::max(most, n);
        };
        const std::vector<PixelWindow> all = windowed ? s.windows : std::vector<PixelWindow>{{0, 0, s.width, s.height}};
        for (const PixelWindow& w : all)
            for (int y = w.y; y < w.y + w.height; ++y)
                for (int x = w.x; x < w.x + w.width; ++x) count(x, y);
        out.spp = least == most ? least : 0;
    }
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
