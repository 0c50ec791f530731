// The bin executor against raw Embree on the very same rays, in one run (issue 4):
//   build/release/bench/render_bench
// BM_BinExecutor renders the built-in Cornell box with (TTMRSGD)*; BM_RawEmbree replays every
// ray that render traced (rtcIntersect1M) and every shadow ray (rtcOccluded1M) with no
// shading, no bins and no film. The overhead ratio is the first time over the second.
// Both run at 1 and 2 threads for scaling.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "compiler/crex/compile.h"
#include "runtime/render/render.h"
#include "runtime/render/render_scene.h"
#include "runtime/scene/load_scene.h"
#include "runtime/trace/trace_batch.h"

namespace {

using namespace crex;

constexpr int kSize = 128;
constexpr uint32_t kSpp = 4;

sched::Program program() {
    SourceFile f("<bench>", "(TTMRSGD)*");
    DiagnosticSink sink;
    return *compile_crex(f, sink).program;
}

RenderOptions options(RayCapture* capture) {
    RenderOptions o;
    o.width = o.height = kSize;
    o.spp = kSpp;
    o.executor.shade.capture = capture;
    return o;
}

void BM_BinExecutor(benchmark::State& state) {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(state.range(0)));
    Scene scene = *builtin_scene("cornell");
    sched::Program p = program();
    uint64_t rays = 0;
    for (auto _ : state) {
        RenderResult r = render(scene, p, options(nullptr));
        rays = r.stats.camera.rays + r.stats.camera.shadow_rays;
        for (const auto& c : r.stats.components) rays += c.rays + c.shadow_rays;
        state.SetIterationTime(r.render_seconds);  // excludes the BVH build, like the raw replay
    }
    state.counters["Mrays/s"] = benchmark::Counter(static_cast<double>(rays) * static_cast<double>(state.iterations()) / 1e6,
                                                   benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BinExecutor)->Arg(1)->Arg(2)->UseManualTime()->Unit(benchmark::kMillisecond);

void BM_RawEmbree(benchmark::State& state) {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(state.range(0)));
    Scene scene = *builtin_scene("cornell");
    RayCapture capture;
    render(scene, program(), options(&capture));
    RenderScene rs(scene);
    for (auto _ : state) {
        state.PauseTiming();
        std::vector<RTCRayHit> rays = capture.rays;
        std::vector<RTCRay> shadows = capture.shadow_rays;
        state.ResumeTiming();
        intersect_batch(*rs.embree, rays.data(), rays.size(), false);
        occluded_batch(*rs.embree, shadows.data(), shadows.size());
        benchmark::DoNotOptimize(rays.data());
    }
    state.counters["Mrays/s"] = benchmark::Counter(
        static_cast<double>(capture.rays.size() + capture.shadow_rays.size()) * static_cast<double>(state.iterations()) / 1e6,
        benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RawEmbree)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
