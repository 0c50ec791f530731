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

ReferenceImage reference_image_of(const ReferencePixels& s, RenderedPixels pixels, const std::string& scene, const std::string& scene_hash,
                                  const std::string& crex, const FrameContext* context) {
    const std::vector<PixelWindow> windows = s.windows.empty() ? std::vector<PixelWindow>{{0, 0, s.width, s.height}} : s.windows;
    const WindowAtlas atlas(windows);
    ReferenceImage image;
    image.width = atlas.width, image.height = atlas.height;
    image.rgb = std::move(pixels.rgb);
    ReferenceHeader& h = image.header;
    h.frame_width = s.width, h.frame_height = s.height, h.windows = windows, h.spp = pixels.spp, h.seed = s.seed;
    h.scene = scene, h.scene_hash = scene_hash, h.crex = crex;
    h.runs = std::to_string(pixels.spp), h.render_seconds = pixels.seconds;
    if (context && !context->rgb.empty()) {
        h.exposure = context->exposure, h.context = context->how;
        if (!context->saliency.empty()) image.attention = atlas.pack(context->saliency, s.width, 1);
    }
    return image;
}

ReferencePixels more_samples_of(const ReferenceHeader& h, uint32_t more) {
    ReferencePixels s;
    s.width = h.frame_width, s.height = h.frame_height;
    if (!h.whole_frame()) s.windows = h.windows;
    s.first_sample = h.spp, s.spp = more, s.seed = h.seed;
    return s;
}

void add_samples(ReferenceImage& ref, const RenderedPixels& more) {
    ReferenceHeader& h = ref.header;
    // The file's mean and the new samples' are independent: how far apart they are says how
    // far the sum of both still is from converged.
    h.own_rmse = own_rmse_estimate(ref.rgb, h.spp, more.rgb, more.spp);
    ref.rgb = accumulate_samples(ref.rgb, h.spp, more.rgb, more.spp);
    h.runs = (h.runs.empty() ? std::to_string(h.spp) : h.runs) + "+" + std::to_string(more.spp);
    h.spp += more.spp;
    h.render_seconds += more.seconds;
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
