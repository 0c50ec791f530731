// Filing records into the irradiance cache (runtime/cache/irradiance_cache.h), in one run:
//   build/release/bench/cache_bench
// Every later frame of a walk starts a new cache from the records the frames before made
// (136,000 on the living-room dolly), and files each into the grids of its bounce level before
// the frame's first camera ray. BM_FileRecords files the records of the built-in Cornell box's
// cache (made once, at every bounce level) into a fresh cache: one insert() a record (mode 0),
// or all in one insert() (mode 1: room made first, the levels filed side by side). At 1 and 2
// threads; the ratio of the two modes at 2 threads is what a frame gains.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <vector>

#include "runtime/base/sampling.h"
#include "runtime/cache/irradiance_cache.h"
#include "runtime/render/render_scene.h"
#include "runtime/scene/load_scene.h"

namespace crex {
namespace {

// The Cornell box's records: queries on a grid over its floor, ceiling and back wall, answered
// by a cache that makes what is missing at every bounce level.
struct Records {
    Records() : rs(scene) {
        settings.divisions = 64;
        settings.bounces = 8;
        settings.caustic_photons = 0;
        IrradianceCache cache(rs, settings);
        const Vec3 offset = rs.embree->origin_offset();
        std::vector<IcQuery> queries;
        for (int wall = 0; wall < 3; ++wall)
            for (int i = 0; i < 160; ++i)
                for (int j = 0; j < 160; ++j) {
                    const double a = -0.99 + 1.98 * i / 159, b = -0.99 + 1.98 * j / 159;
                    IcQuery q;
                    q.position = (wall == 0 ? Vec3{a, -0.999, b} : wall == 1 ? Vec3{a, 0.997, b} : Vec3{a, b, -0.999}) - offset;
                    q.normal = wall == 0 ? Vec3{0, 1, 0} : wall == 1 ? Vec3{0, -1, 0} : Vec3{0, 0, 1};
                    q.key = mix64(queries.size());
                    queries.push_back(q);
                }
        std::vector<Vec3> out;
        cache.irradiance(queries, 0, out);
        records = cache.records();
    }
    Scene scene = *builtin_scene("cornell");
    RenderScene rs;
    IcSettings settings;
    std::vector<IrradianceRecord> records;
};

const Records& made() {
    static const Records r;
    return r;
}

void BM_FileRecords(benchmark::State& state) {
    const Records& r = made();
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(state.range(0)));
    for (auto _ : state) {
        IrradianceCache cache(r.rs, r.settings);
        if (state.range(1) == 0)
            for (const IrradianceRecord& rec : r.records) cache.insert(rec);
        else
            cache.insert(r.records);
        benchmark::DoNotOptimize(cache.records().data());
    }
    state.counters["records"] = static_cast<double>(r.records.size());
    double largest = 0;  // the share of the most populous bounce level: what bounds filing them side by side
    for (uint32_t level = 0; level < r.settings.bounces; ++level)
        largest = std::max(largest, static_cast<double>(std::count_if(r.records.begin(), r.records.end(),
                                                                      [&](const IrradianceRecord& rec) { return rec.level == level; })));
    state.counters["largest_level_share"] = largest / static_cast<double>(r.records.size());
}
// Arguments: threads, mode (0: one insert() a record, 1: one insert() for all).
BENCHMARK(BM_FileRecords)->ArgsProduct({{1, 2}, {0, 1}})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace crex

BENCHMARK_MAIN();
