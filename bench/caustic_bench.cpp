// The caustic photon map's cost (runtime/cache/caustic_photons.h), in one run:
//   build/release/bench/caustic_bench
// BM_CausticMapBuild: emitting, tracing and storing the photons, the k-d trees and the
// density estimates, on the built-in Cornell box (a mirror and a glass ball under one lamp).
// BM_CausticMapQuery: irradiance at camera-like queries on the floor and the ceiling, per
// query. Both at 1 and 2 threads (queries are independent: the driver runs them in parallel)
// and at 50,000, 200,000 (the default) and 800,000 photons.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <vector>

#include "runtime/cache/caustic_photons.h"
#include "runtime/render/render_scene.h"
#include "runtime/scene/load_scene.h"

namespace crex {
namespace {

// The Cornell box and the map's settings from a benchmark's arguments (threads, photons).
struct Setup {
    explicit Setup(const benchmark::State& state)
        : threads(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(state.range(0))), rs(scene) {
        settings.photons = static_cast<uint32_t>(state.range(1));
    }
    tbb::global_control threads;
    Scene scene = *builtin_scene("cornell");
    RenderScene rs;
    CausticPhotonSettings settings;
};

void BM_CausticMapBuild(benchmark::State& state) {
    Setup s(state);
    size_t stored = 0;
    for (auto _ : state) {
        CausticPhotons map(s.rs, s.settings);
        stored = map.size();
        benchmark::DoNotOptimize(stored);
    }
    state.counters["stored"] = static_cast<double>(stored);
}
// Arguments: threads, photons emitted.
BENCHMARK(BM_CausticMapBuild)->ArgsProduct({{1, 2}, {50000, 200000, 800000}})->Unit(benchmark::kMillisecond);

void BM_CausticMapQuery(benchmark::State& state) {
    Setup s(state);
    CausticPhotons map(s.rs, s.settings);
    // A 128 x 128 grid on the floor (the glass ball's caustic) and one on the ceiling (the
    // mirror ball's), in local coordinates.
    std::vector<std::pair<Vec3, Vec3>> queries;
    const Vec3 offset = s.rs.embree->origin_offset();
    for (double y : {-0.999, 0.997})
        for (int i = 0; i < 128; ++i)
            for (int j = 0; j < 128; ++j)
                queries.push_back({Vec3{-0.99 + 1.98 * i / 127, y, -0.99 + 1.98 * j / 127} - offset, Vec3{0, y < 0 ? 1.0 : -1.0, 0}});
    std::vector<Vec3> out(queries.size());
    for (auto _ : state) {
        tbb::parallel_for(size_t{0}, queries.size(), [&](size_t q) { out[q] = map.irradiance(queries[q].first, queries[q].second); });
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(queries.size()));
}
BENCHMARK(BM_CausticMapQuery)->ArgsProduct({{1, 2}, {50000, 200000, 800000}})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace crex

BENCHMARK_MAIN();
