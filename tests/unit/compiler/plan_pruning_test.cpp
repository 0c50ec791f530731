// Scene-aware analysis (spec/crex.md §5): steps whose bins the scene can never fill are found
// and pruned, and what is left executes exactly as before.
#include <gtest/gtest.h>

#include "compiler/plan/bin_occupancy.h"
#include "compiler/plan/emit_plan.h"
#include "compiler/sched/print.h"
#include "runtime/scene/census.h"
#include "runtime/scene/load_scene.h"
#include "tests/support/plan_helpers.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

using testing::bins;

std::string pruned_text(const std::string& crex, const std::string& spawnable) {
    return sched::to_crex(prune_dead_steps(testing::lower_or_die(crex), bins(spawnable)));
}

std::string dead_letters(const std::string& crex, const std::string& spawnable) {
    std::string out;
    for (const auto& d : find_dead_steps(testing::lower_or_die(crex), bins(spawnable))) out += component_letter(d.component);
    return out;
}

TEST(PlanPruning, AllDiffuseSceneKeepsOnlyD) {
    EXPECT_EQ(pruned_text("(TTMRSGD)*", "D"), "D*");
    EXPECT_EQ(dead_letters("(TTMRSGD)*", "D"), "TTMRSG");
    // With the real census of the diffuse-only box.
    Census c = take_census(*builtin_scene("cornell_diffuse"));
    EXPECT_EQ(sched::to_crex(prune_dead_steps(testing::lower_or_die("(TTMRSGD)*"), c.spawnable)), "D*");
}

TEST(PlanPruning, KeepsWhatTheSceneCanFill) {
    Census c = take_census(*builtin_scene("cornell"));  // D T R M
    EXPECT_EQ(sched::to_crex(prune_dead_steps(testing::lower_or_die("TT{TTMRSGD}2"), c.spawnable)), "TT{TTMRD}2");
    EXPECT_EQ(pruned_text("(TT[RS]G)*D", "DTRM"), "(TT[R])*D");
    EXPECT_EQ(pruned_text("(TT[RS]G)*D", "D"), "D");
    EXPECT_EQ(pruned_text("<SG>", "D"), "");
}

TEST(PlanPruning, ModulationNumberingIsKept) {
    // {TD} on a diffuse scene: D stays occurrence 1 of n = 2, as before pruning.
    sched::Program p = prune_dead_steps(testing::lower_or_die("{TD}"), bins("D"));
    const sched::Node& m = p.selective.children.at(0);
    ASSERT_EQ(m.op, sched::Op::kModulate);
    EXPECT_EQ(m.occurrences, 2);
    ASSERT_EQ(m.children.size(), 1u);
    EXPECT_EQ(m.children[0].first_index, 1);
}

TEST(PlanPruning, DeferralDelaysWhatBecomesReachable) {
    // In a scene of mirrors only, M is reachable from the camera; nothing else ever is.
    EXPECT_EQ(dead_letters("MD", "M"), "D");
    EXPECT_EQ(dead_letters("<M>M", "M"), "");
    EXPECT_EQ(dead_letters("", "DTRM"), "");
}

TEST(PlanPruning, DeadStepsCarryTheirPositionAndReason) {
    auto dead = find_dead_steps(testing::lower_or_die("D(TG)"), bins("D"));
    ASSERT_EQ(dead.size(), 2u);
    EXPECT_EQ(dead[0].where.col, 3u);
    EXPECT_EQ(dead[1].where.col, 4u);
    EXPECT_NE(dead[0].reason.find("glass, dielectric"), std::string::npos) << dead[0].reason;
}

TEST(PlanEmit, JsonIsVersionedListsPrunedStepsAndIsByteStable) {
    CrexPlan plan;
    plan.source = "(TTMRSGD)*";
    sched::Program p = testing::lower_or_die(plan.source);
    Census c = take_census(*builtin_scene("cornell_diffuse"));
    plan.pruned = find_dead_steps(p, c.spawnable);
    plan.program = prune_dead_steps(p, c.spawnable);
    plan.scene = "builtin:cornell_diffuse";
    plan.census_hash = census_hash_hex(c.hash);
    nlohmann::json j = plan_to_json(plan);
    EXPECT_EQ(j["format"], "crex-plan");
    EXPECT_EQ(j["version"], kPlanFormatVersion);
    EXPECT_EQ(j["crex"]["canonical"], "D*");
    EXPECT_EQ(j["pruned"].size(), 6u);
    EXPECT_EQ(j["stages"]["preselective"]["children"][0]["op"], "repeat_until_empty");
    EXPECT_EQ(plan_to_json(plan).dump(2), j.dump(2));
    std::string dot = plan_to_dot(plan);
    EXPECT_NE(dot.find("subgraph cluster_pruned"), std::string::npos);
    EXPECT_NE(dot.find("* while work"), std::string::npos);
}

}  // namespace
}  // namespace crex
