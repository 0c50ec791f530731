// A pipeline of 100,000 maps through the whole front end (issue 37: checking was quadratic in
// the maps, 50,000 unused ones took more than 60 s). Label `scale`: Release only (about 2 s of
// CPU and 400 MB there; under ASan it is minutes of a CI's time). How the time grows is bench/'s to measure
// (crex_frontend_bench BM_PlanUsedMaps, BM_PlanUnusedMaps), not a wall-clock assert here.
#include <gtest/gtest.h>

#include <string>

#include "compiler/pipeline/check.h"
#include "compiler/pipeline/parse.h"
#include "compiler/pipeline/resolve.h"
#include "compiler/plan/plan_pipeline.h"

namespace crex {
namespace {

constexpr int kMaps = 100000;

std::string pipeline_of_maps(int maps, bool used) {
    std::string text = "pipeline many {\n  preselective { crex \"TT\" }\n  guidance {\n";
    for (int i = 0; i < maps; ++i) text += "    m" + std::to_string(i) + " = saliency(preview)\n";
    if (used) {
        text += "    all = importance(";
        for (int i = 0; i < maps; ++i) text += (i ? ", m" : "m") + std::to_string(i) + " 1";
        text += ")\n";
    }
    text += std::string("  }\n  selective { vary spp 1 .. 4 by ") + (used ? "all" : "m0") + " }\n}\n";
    return text;
}

// Unused maps: each is W201 (counted, at most 100 kept), and the planner prunes them all.
TEST(PipelineScale, AHundredThousandUnusedMapsAreCheckedAndPruned) {
    SourceFile file("many.pipe", pipeline_of_maps(kMaps, false));
    DiagnosticSink sink;
    auto ast = pipeline::parse_pipeline_file(file, sink);
    ASSERT_TRUE(ast);
    pipeline::check_pipeline_file(*ast, sink);
    EXPECT_EQ(sink.error_count(), 0u);
    EXPECT_EQ(sink.warning_count(), static_cast<size_t>(kMaps - 1));  // m0 is used
    auto resolved = pipeline::resolve_pipeline(*ast, "", sink);
    ASSERT_TRUE(resolved);
    EXPECT_EQ(resolved->maps.size(), static_cast<size_t>(kMaps));
    auto plan = plan_pipeline(*resolved, std::nullopt, "", "", sink);
    ASSERT_TRUE(plan);
    EXPECT_EQ(plan->pruned.size(), static_cast<size_t>(kMaps - 1));
}

// Used maps: one importance() of them all, so the planner builds a node and an edge for each
// (25,000 of them: one call of 100,000 arguments parses into 600 MB of tree).
TEST(PipelineScale, TwentyFiveThousandUsedMapsArePlanned) {
    constexpr int kUsed = 25000;
    SourceFile file("many.pipe", pipeline_of_maps(kUsed, true));
    DiagnosticSink sink;
    auto ast = pipeline::parse_pipeline_file(file, sink);
    ASSERT_TRUE(ast);
    pipeline::check_pipeline_file(*ast, sink);
    EXPECT_EQ(sink.error_count(), 0u);
    EXPECT_EQ(sink.warning_count(), 0u);
    auto resolved = pipeline::resolve_pipeline(*ast, "", sink);
    ASSERT_TRUE(resolved);
    auto plan = plan_pipeline(*resolved, std::nullopt, "", "", sink);
    ASSERT_TRUE(plan);
    EXPECT_EQ(plan->maps.size(), static_cast<size_t>(kUsed + 1));
    EXPECT_TRUE(plan->pruned.empty());
}

}  // namespace
}  // namespace crex
