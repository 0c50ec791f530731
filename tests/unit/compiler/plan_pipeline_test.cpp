// Planning pipelines: the typed graph of the normative example, pruning for a scene, and
// golden snapshots (JSON and DOT) of every stdlib pipeline on the two Cornell boxes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "compiler/sched/print.h"
#include "tests/support/plan_helpers.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

const PlanNode* node(const PipelinePlan& p, const std::string& id) {
    for (const auto& n : p.nodes)
        if (n.id == id) return &n;
    return nullptr;
}

bool edge(const PipelinePlan& p, const std::string& from, const std::string& to, const std::string& kind) {
    for (const auto& e : p.edges)
        if (e.from == from && e.to == to && e.kind == kind) return true;
    return false;
}

using testing::bins;

TEST(PlanPipeline, NormativeExampleIsATypedGraph) {
    auto r = testing::plan_text("examples/pipelines/cornell_prog.pipe",
                                testing::read_text(CREX_SOURCE_DIR "/examples/pipelines/cornell_prog.pipe"), bins("DTRM"));
    ASSERT_TRUE(r.plan) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const PipelinePlan& p = *r.plan;
    EXPECT_EQ(p.chain, (std::vector<std::string>{"cornell_prog", "prog_dis_all"}));
    for (const char* id : {"camera", "preselective", "preview", "map.sal", "map.ic", "map.task", "map.imp", "vary.spp",
                           "vary.ic_radius", "vary.shadow_rays", "selective", "irradiance_cache", "composite"})
        EXPECT_NE(node(p, id), nullptr) << id;
    EXPECT_TRUE(edge(p, "camera", "preselective", "bin"));
    EXPECT_TRUE(edge(p, "preview", "map.sal", "image"));
    EXPECT_TRUE(edge(p, "map.sal", "map.imp", "map"));
    EXPECT_TRUE(edge(p, "map.imp", "selective", "map"));  // modulates the { } groups
    EXPECT_TRUE(edge(p, "vary.spp", "selective", "svt"));
    EXPECT_TRUE(edge(p, "preselective", "selective", "bin"));
    EXPECT_EQ(sched::to_crex(p.program.preselective), "TTD");  // D fills edges(component(D))
    EXPECT_EQ(sched::to_crex(p.program.selective), "{TTMRD}2");  // S and G cannot occur with these bins
    // prog_dis_all's `dl` drove shadow_rays; cornell_prog varies them by edges(direct) instead.
    bool dl_pruned = false;
    for (const auto& pr : p.pruned) dl_pruned |= pr.what == "map dl";
    EXPECT_TRUE(dl_pruned);
}

TEST(PlanPipeline, DiffuseSceneKeepsOnlyDAndSaysWhy) {
    auto r = testing::plan_text("stdlib/pipelines/gold.pipe", testing::read_text(CREX_SOURCE_DIR "/stdlib/pipelines/gold.pipe"),
                                bins("D"));
    ASSERT_TRUE(r.plan);
    EXPECT_EQ(sched::to_crex(r.plan->program.preselective), "D*");
    std::string removed;
    for (const auto& pr : r.plan->pruned) removed += pr.what.back();
    EXPECT_EQ(removed, "TTMRSG");
}

TEST(PlanPipeline, WithoutADStepTheIrradianceCacheGoes) {
    // A scene of mirrors only: no D step survives, so ic_radius, the cache and the map that
    // only fed it are all removed, each with its reason.
    auto r = testing::plan_text("stdlib/pipelines/prog_dis_all.pipe",
                                testing::read_text(CREX_SOURCE_DIR "/stdlib/pipelines/prog_dis_all.pipe"), bins("M"));
    ASSERT_TRUE(r.plan);
    std::vector<std::string> what;
    for (const auto& pr : r.plan->pruned) what.push_back(pr.what);
    for (const char* w : {"vary ic_radius", "irradiance cache", "map ic"})
        EXPECT_NE(std::find(what.begin(), what.end(), w), what.end()) << w;
    EXPECT_EQ(node(*r.plan, "irradiance_cache"), nullptr);
    EXPECT_EQ(node(*r.plan, "vary.ic_radius"), nullptr);
    EXPECT_NE(node(*r.plan, "vary.spp"), nullptr);
}

// Golden snapshots: every stdlib pipeline on the full and the diffuse-only Cornell box, as JSON
// and DOT, compared byte for byte. CREX_UPDATE_GOLDEN=1 rewrites them (review the diff).
TEST(PlanGolden, StdlibPipelinesOnBothCornellBoxes) {
    bool update = std::getenv("CREX_UPDATE_GOLDEN") != nullptr;
    std::vector<fs::path> pipes;
    for (const auto& e : fs::directory_iterator(CREX_SOURCE_DIR "/stdlib/pipelines")) pipes.push_back(e.path());
    std::sort(pipes.begin(), pipes.end());
    ASSERT_GE(pipes.size(), 13u);
    int compared = 0;
    for (const auto& pipe : pipes) {
        for (const char* scene_name : {"cornell", "cornell_diffuse"}) {
            Census census = take_census(*builtin_scene(scene_name));
            std::string rel = "stdlib/pipelines/" + pipe.filename().string();
            auto r = testing::plan_text(rel, testing::read_text(pipe.string()), census.spawnable,
                                        std::string("builtin:") + scene_name, census_hash_hex(census.hash));
            ASSERT_TRUE(r.plan) << rel << ": " << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
            std::string json = pipeline_plan_to_json(*r.plan).dump(2) + "\n";
            std::string dot = pipeline_plan_to_dot(*r.plan);
            // Deterministic: planning again gives the same bytes.
            auto again = testing::plan_text(rel, testing::read_text(pipe.string()), census.spawnable,
                                            std::string("builtin:") + scene_name, census_hash_hex(census.hash));
            ASSERT_EQ(pipeline_plan_to_json(*again.plan).dump(2) + "\n", json);
            std::string stem = pipe.stem().string() + "." + scene_name;
            for (const auto& [ext, text] : {std::pair<std::string, std::string>{".plan.json", json}, {".plan.dot", dot}}) {
                fs::path golden = fs::path(CREX_SOURCE_DIR "/tests/golden/plans") / (stem + ext);
                if (update) {
                    std::ofstream(golden) << text;
                    continue;
                }
                ASSERT_TRUE(fs::exists(golden)) << golden << " is missing: run with CREX_UPDATE_GOLDEN=1";
                EXPECT_EQ(testing::read_text(golden.string()), text) << golden << " differs (CREX_UPDATE_GOLDEN=1 rewrites)";
                ++compared;
            }
        }
    }
    if (!update) {
        EXPECT_EQ(compared, static_cast<int>(pipes.size()) * 4);
    }
}

}  // namespace
}  // namespace crex
