// A run's options resolved against a plan (runtime/api/run_options.h): what no render can
// use is refused there, for every caller of the library, not only by `crex run`'s flags and
// Python's keyword checks (spp 0 from C++ rendered a black image of 0 rays without a word).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "runtime/api/run_options.h"
#include "runtime/scene/load_scene.h"
#include "tests/support/plan_helpers.h"

namespace crex {
namespace {

TEST(RunOptions, ValuesNoRenderCanUseAreRefusedNamingTheSetting) {
    const Scene scene = *builtin_scene("cornell");
    const PipelinePlan plan = testing::plan_for("pipeline p { preselective { crex \"(TTMRSGD)*\" spp 2 } }", scene);
    EXPECT_EQ(resolve_run(plan, RunOptions{}).settings.spp, 2u);  // the plan's own settings resolve
    struct Case {
        void (*set)(RunOptions&);
        const char* says;
    };
    const Case cases[] = {
        {[](RunOptions& o) { o.spp = 0; }, "spp: at least 1"},
        {[](RunOptions& o) { o.width = 0; }, "a width and a height of at least 1"},
        {[](RunOptions& o) { o.height = -3; }, "a width and a height of at least 1"},
        {[](RunOptions& o) { o.shadow_rays = 0; }, "shadow_rays: 1 to 1024"},
        {[](RunOptions& o) { o.media_samples = 5000; }, "media_samples: 1 to 1024"},
        {[](RunOptions& o) { o.lw = std::nan(""); }, "lw: a weight limit from 0 to 1"},
        {[](RunOptions& o) { o.ambient = AmbientStandIn{false, -1}; }, "ambient: a radiance of 0 or more"},
    };
    for (const Case& c : cases) {
        RunOptions o;
        c.set(o);
        try {
            resolve_run(plan, o);
            ADD_FAILURE() << "accepted: " << c.says;
        } catch (const RunOptionError& e) {
            EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace crex
