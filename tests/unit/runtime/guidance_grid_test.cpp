// Guidance after a strided preview (runtime/pipeline/guidance_grid.h, issue 34): the grid is the
// pixels a preview at stride k sampled; the probe traces them alone, and the maps of what they see
// are made there and spread over the frame as the preview itself is.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/driver/run_plan.h"
#include "runtime/pipeline/guidance_graph.h"
#include "runtime/pipeline/guidance_grid.h"
#include "runtime/pipeline/pixel_probe.h"
#include "runtime/pipeline/subsample.h"
#include "runtime/render/render_scene.h"
#include "runtime/scene/load_scene.h"
#include "tests/support/plan_helpers.h"

namespace crex {
namespace {

TEST(GuidanceGrid, HoldsThePixelsAPreviewAtItsStrideSampled) {
    for (auto [w, h] : {std::pair{1, 1}, {7, 5}, {33, 17}, {40, 24}})
        for (uint32_t k : {1u, 2u, 4u, 8u}) {
            const GuidanceGrid grid(w, h, k);
            const SubsampleGrid preview(w, h, std::vector<double>(static_cast<size_t>(w) * static_cast<size_t>(h), k));
            EXPECT_EQ(static_cast<uint64_t>(grid.width()) * static_cast<uint64_t>(grid.height()), preview.rendered_count()) << w << "x" << h;
            for (int y : grid.rows())
                for (int x : grid.columns())
                    EXPECT_TRUE(preview.rendered(static_cast<uint32_t>(y * w + x))) << x << "," << y << " every " << k;
        }
}

// Bilinear interpolation is exact for a function bilinear in x and y: sampled on the grid and
// spread, such a map is itself, whatever the stride and the uneven last square.
TEST(GuidanceGrid, ABilinearMapSpreadFromTheGridIsItself) {
    const int w = 37, h = 21;
    auto f = [](int x, int y, int c) { return 0.25f + 0.01f * x - 0.02f * y + 0.0005f * x * y + static_cast<float>(c); };
    for (uint32_t k : {1u, 3u, 8u}) {
        const GuidanceGrid grid(w, h, k);
        guidance::Raster small(grid.width(), grid.height(), 2);
        for (int j = 0; j < grid.height(); ++j)
            for (int i = 0; i < grid.width(); ++i)
                for (int c = 0; c < 2; ++c) small.at(i, j, c) = f(grid.columns()[size_t(i)], grid.rows()[size_t(j)], c);
        const guidance::Raster back = grid.spread(small);
        ASSERT_EQ(back.width, w);
        ASSERT_EQ(back.height, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 2; ++c) ASSERT_NEAR(back.at(x, y, c), f(x, y, c), 1e-5f) << x << "," << y << " every " << k;
    }
}

TEST(GuidanceGrid, TheProbeOfTheGridsPixelsIsTheFullProbeThere) {
    const Scene scene = *builtin_scene("cornell");
    const RenderScene rs(scene);
    const int w = 40, h = 30;
    const PixelProbe full = probe_pixels(rs, w, h);
    const GuidanceGrid grid(w, h, 4);
    const PixelProbe part = probe_pixels(rs, w, h, grid.columns(), grid.rows());
    ASSERT_EQ(part.width, grid.width());
    ASSERT_EQ(part.height, grid.height());
    for (size_t j = 0; j < grid.rows().size(); ++j)
        for (size_t i = 0; i < grid.columns().size(); ++i) {
            const size_t p = static_cast<size_t>(grid.rows()[j] * w + grid.columns()[i]), q = j * grid.columns().size() + i;
            EXPECT_EQ(part.shape[q], full.shape[p]);
            EXPECT_EQ(part.detected[q], full.detected[p]);
            EXPECT_EQ(part.distance[q], full.distance[p]);
            EXPECT_EQ(part.normal[q], full.normal[p]);
        }
}

double correlation(const std::vector<float>& a, const std::vector<float>& b) {
    double ma = 0, mb = 0;
    for (size_t p = 0; p < a.size(); ++p) ma += a[p], mb += b[p];
    ma /= static_cast<double>(a.size()), mb /= static_cast<double>(b.size());
    double ab = 0, aa = 0, bb = 0;
    for (size_t p = 0; p < a.size(); ++p) {
        const double x = a[p] - ma, y = b[p] - mb;
        ab += x * y, aa += x * x, bb += y * y;
    }
    return aa * bb > 0 ? ab / std::sqrt(aa * bb) : 0.0;
}

// The same pipeline on the same strided preview: the maps made after it are frame-sized, the
// image's (saliency) are the ones made on the whole interpolated preview, and those of what the
// pixels see (the task map, and what it enters) agree with the ones made from a probe of every
// pixel (correlation over the frame: a task map's edge moves by at most a grid square).
TEST(GuidanceGrid, AStridedPreviewsMapsOfWhatPixelsSeeAreMadeOnItsGrid) {
    Scene scene = *builtin_scene("cornell");
    for (Shape& s : scene.shapes)
        if (s.name == "glass_ball") s.tag = Tag{"ball", 3, false};
    const PipelinePlan plan = testing::plan_for(
        "pipeline p {\n preselective { crex \"(TTMRSGD)*\" spp 1 }\n"
        " guidance { sal = saliency(preview)\n task = task_map(tagged(), fovea 2 deg)\n"
        "   imp = importance(task 0.5, sal 0.5, op \"+\") }\n selective { vary spp 1 .. 2 by imp }\n}\n",
        scene);
    const int w = 96, h = 72;
    RunSettings s;
    s.width = w, s.height = h;
    s.preview_stride = 4;
    const RunResult r = run_plan(scene, plan, s);
    ASSERT_EQ(r.preview_stride, 4u);
    ASSERT_EQ(r.maps.size(), 3u);
    const RenderScene rs(scene);
    const PixelProbe probe = probe_pixels(rs, w, h);
    GuidanceInputs in;
    in.width = w, in.height = h;
    in.preview = r.preview;
    in.scene = &scene;
    in.probe = &probe;
    GuidanceGraph whole(plan, std::move(in));
    for (const auto& [name, map] : r.maps) {
        ASSERT_EQ(map.width, w) << name;
        ASSERT_EQ(map.height, h) << name;
        const PlanMap* m = nullptr;
        for (const PlanMap& pm : plan.maps)
            if (pm.defines == name) m = &pm;
        ASSERT_NE(m, nullptr) << name;
        const std::vector<float>& frame = whole.map(m->id).v;
        if (name == "sal") {
            EXPECT_EQ(map.v, frame) << "saliency is made on the frame";
            continue;
        }
        EXPECT_GT(correlation(map.v, frame), 0.95) << name << ": the grid's map is not where the frame's is";
        EXPECT_NE(map.v, frame) << name << ": made on the frame, not on the grid";
    }
}

}  // namespace
}  // namespace crex
