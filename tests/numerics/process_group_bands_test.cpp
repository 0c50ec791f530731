// Distributed rendering without mpirun (issue 35): the driver renders through a ProcessGroup,
// so a group of threads (tests/support/thread_group.h), each rendering its band of rows and
// exchanging rows as MPI ranks do, must give the image one process renders: a pixel is the
// sum of the samples one member traced, in the order one process traces them. Up to the last
// bits of a float: Embree's ray streams (rtcIntersect1M) trace a ray with the others of its
// direction's octant in the same call, so a band's rays meet other neighbours than the whole
// image's, and a hit's distance can round one way or the other (a glass path 12 bounces deep
// in the Cornell box: one pixel 1 float ulp apart in 3 bands). Tracing ray by ray would make
// them equal bit for bit, and a render about a quarter slower (render_bench, one thread).
// The same property under mpirun is tests/mpi/; this one runs in every CI job.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/api/run.h"
#include "runtime/api/run_inputs.h"
#include "tests/support/test_scenes.h"
#include "tests/support/thread_group.h"

namespace crex {
namespace {

// Equal to the rounding of a float's last bits: every value within 1e-6 of the other's size.
void expect_same_image(const std::vector<float>& banded, const std::vector<float>& one, int bands) {
    ASSERT_EQ(banded.size(), one.size()) << bands << " bands";
    size_t apart = 0;
    for (size_t i = 0; i < one.size(); ++i)
        if (!(std::fabs(banded[i] - one[i]) <= 1e-6 * std::fmax(std::fabs(one[i]), 1e-3))) ++apart;
    EXPECT_EQ(apart, 0u) << bands << " bands: values further apart than rounding";
}

// The final image of `plan` rendered by one process (bands 0) or a group of `bands` threads.
std::vector<float> render_in(int bands, const PipelinePlan& plan, const Scene& scene, const RunSettings& settings) {
    if (bands == 0) return run_plan(scene, plan, settings).image();
    testing::ThreadGroup group(bands);
    std::vector<float> image;
    group.run([&](ProcessGroup& member) {
        RunObserver nobody;
        RunResult result = run_plan(scene, plan, settings, member, nobody);
        EXPECT_EQ(result.row_bands.size(), static_cast<size_t>(bands) + 1);
        if (member.leads()) image = result.image();
    });
    return image;
}

// A stdlib pipeline planned for the built-in Cornell box, with the run's options resolved.
struct Planned {
    std::unique_ptr<PipelineInput> input;
    RunSettings settings;
};

Planned plan_stdlib(const std::string& name, RunOptions options) {
    Planned p;
    DiagnosticSink sink;
    p.input = load_pipeline_input(CREX_SOURCE_DIR "/stdlib/pipelines/" + name, "", "builtin:cornell", sink);
    EXPECT_FALSE(sink.has_errors());
    EXPECT_TRUE(p.input->compiled.plan);
    p.settings = resolve_run(*p.input->compiled.plan, options).settings;
    return p;
}

TEST(ProcessGroupBands, ACrexRendersTheSingleProcessImageInTwoAndThreeBands) {
    PipelinePlan plan;
    plan.program = testing::lower_or_die("(TTMRSGD)*");
    RunSettings s;
    s.width = 24, s.height = 17, s.spp = 4;
    const Scene scene = *builtin_scene("cornell");
    const std::vector<float> one = render_in(0, plan, scene, s);
    expect_same_image(render_in(2, plan, scene, s), one, 2);
    expect_same_image(render_in(3, plan, scene, s), one, 3);
}

TEST(ProcessGroupBands, APipelineRendersTheSingleProcessImageInTwoBands) {
    // Guidance sees the whole preview on every member; the selective samples go by bands of
    // about the same camera samples.
    RunOptions o;
    o.width = 24, o.height = 16;
    const Planned p = plan_stdlib("sel_rp.pipe", o);
    const Scene& scene = *p.input->scene->scene;
    const std::vector<float> one = render_in(0, *p.input->compiled.plan, scene, p.settings);
    expect_same_image(render_in(2, *p.input->compiled.plan, scene, p.settings), one, 2);
}

TEST(ProcessGroupBands, APipelineThatCarriesRaysRendersTheSingleProcessImage) {
    // cbtcr_sel's "TT" preview leaves rays waiting for the selective stage: they stand in as
    // av in the preview every member's maps see, and the bands move between stages.
    RunOptions o;
    o.width = 32, o.height = 24;
    o.no_budget = true;
    o.ambient = AmbientStandIn{false, 0.3};
    const Planned p = plan_stdlib("cbtcr_sel.pipe", o);
    const Scene& scene = *p.input->scene->scene;
    const std::vector<float> one = render_in(0, *p.input->compiled.plan, scene, p.settings);
    expect_same_image(render_in(2, *p.input->compiled.plan, scene, p.settings), one, 2);
}

}  // namespace
}  // namespace crex
