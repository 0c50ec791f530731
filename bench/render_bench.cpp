// The bin executor against raw Embree on the very same rays, in one run (issue 4):
//   build/release/bench/render_bench
// BM_BinExecutor renders a scene with (TTMRSGD)*; BM_RawEmbree replays every ray that render
// traced (rtcIntersect1M) and every shadow ray (rtcOccluded1M) with no shading, no bins and
// no film. The overhead ratio is the first time over the second. Both run at 1 and 2 threads
// for scaling, on two scenes: the built-in Cornell box (24 triangles and two analytic spheres:
// traversal is as cheap as it gets, so shading weighs most) and the same box with a bumpy
// ball of 262,144 triangles in it (geometry of a modelled scene).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>

#include "compiler/crex/compile.h"
#include "runtime/driver/run_plan.h"
#include "runtime/render/render_scene.h"
#include "runtime/base/sampling.h"
#include "runtime/scene/load_scene.h"
#include "runtime/trace/trace_batch.h"

namespace {

using namespace crex;

constexpr int kSize = 128;
constexpr uint32_t kSpp = 4;

// Scene argument: 0 = builtin:cornell, 1 = the box with a 262,144-triangle bumpy ball.
Scene bench_scene(int64_t which) {
    Scene s = *builtin_scene("cornell");
    if (which == 0) return s;
    Shape ball;
    ball.type = ShapeType::kMesh;
    ball.material = "white";
    ball.name = "bumpy_ball";
    const uint32_t rings = 256, segments = 512;  // 2 x 256 x 512 triangles
    const Vec3 centre{0.25, -0.55, -0.35};
    for (uint32_t i = 0; i <= rings; ++i)
        for (uint32_t j = 0; j < segments; ++j) {
            double theta = kPi * i / rings, phi = 2 * kPi * j / segments;
            double r = 0.4 * (1 + 0.06 * std::sin(12 * theta) * std::sin(12 * phi));
            ball.vertices.push_back(centre + Vec3{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)} * r);
        }
    for (uint32_t i = 0; i < rings; ++i)
        for (uint32_t j = 0; j < segments; ++j) {
            uint32_t a = i * segments + j, b = i * segments + (j + 1) % segments;
            ball.triangles.push_back({a, a + segments, b});
            ball.triangles.push_back({b, a + segments, b + segments});
        }
    s.shapes.push_back(std::move(ball));
    return s;
}

sched::Program program() {
    SourceFile f("<bench>", "(TTMRSGD)*");
    DiagnosticSink sink;
    return *compile_crex(f, sink).program;
}

RunSettings options(RayCapture* capture, size_t chunk_rays = ExecutorOptions{}.chunk_rays) {
    RunSettings o;
    o.width = o.height = kSize;
    o.spp = kSpp;
    o.executor.shade.capture = capture;
    o.executor.chunk_rays = chunk_rays;
    return o;
}

void BM_BinExecutor(benchmark::State& state) {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(state.range(0)));
    Scene scene = bench_scene(state.range(1));
    sched::Program p = program();
    uint64_t rays = 0;
    for (auto _ : state) {
        RunResult r = render(scene, p, options(nullptr, static_cast<size_t>(state.range(2))));
        rays = r.stats.camera.rays + r.stats.camera.shadow_rays;
        for (const auto& c : r.stats.components) rays += c.rays + c.shadow_rays;
        state.SetIterationTime(r.render_seconds);  // excludes the BVH build, like the raw replay
    }
    state.counters["Mrays/s"] = benchmark::Counter(static_cast<double>(rays) * static_cast<double>(state.iterations()) / 1e6,
                                                   benchmark::Counter::kIsRate);
}
// Arguments: threads, scene, rays per chunk (0: the executor's default, 4096 per thread).
BENCHMARK(BM_BinExecutor)
    ->ArgsProduct({{1, 2}, {0, 1}, {0}})
    ->ArgsProduct({{1}, {0, 1}, {65536}})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

void BM_RawEmbree(benchmark::State& state) {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(state.range(0)));
    Scene scene = bench_scene(state.range(1));
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
    // Rays per second as the executor counts them: empty shadow-ray slots (tnear > tfar, which
    // Embree skips in both runs) are not rays.
    size_t shadow_rays = 0;
    for (const RTCRay& r : capture.shadow_rays) shadow_rays += r.tnear <= r.tfar;
    state.counters["Mrays/s"] = benchmark::Counter(
        static_cast<double>(capture.rays.size() + shadow_rays) * static_cast<double>(state.iterations()) / 1e6,
        benchmark::Counter::kIsRate);
}
// Arguments: threads, scene.
BENCHMARK(BM_RawEmbree)->ArgsProduct({{1, 2}, {0, 1}})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
