// The plan reader (compiler/plan/read_plan.cpp): a typed pipeline plan reads back to the same
// JSON, and every kind of damage is a located E401 at the offending value, never an exception,
// a silently dropped stage or a rounded number. Each case damages one golden plan.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <numbers>
#include <sstream>

#include "compiler/plan/plan_pipeline.h"
#include "compiler/plan/read_plan.h"
#include "tests/support/diagnostic_helpers.h"

namespace crex {
namespace {

using nlohmann::json;

json golden(const std::string& name) {
    std::ifstream in(std::string(CREX_SOURCE_DIR "/tests/golden/plans/") + name + ".plan.json");
    std::stringstream text;
    text << in.rdbuf();
    return json::parse(text.str());
}

struct Read : testing::Diagnosed {
    std::unique_ptr<SourceFile> file;
    std::optional<CrexPlan> plan;
    // The plan text at the first diagnostic (what it points at).
    std::string pointed_at(size_t n) const {
        if (diagnostics.empty() || !diagnostics[0].span.valid()) return "";
        return file->text().substr(diagnostics[0].span.begin, n);
    }
};

Read read(const std::string& text) {
    Read r;
    r.file = std::make_unique<SourceFile>("plan.json", text);
    DiagnosticSink sink;
    r.plan = read_plan(*r.file, sink);
    r.diagnostics = sink.sorted();
    r.errors = sink.error_count();
    return r;
}

TEST(PlanReader, EveryGoldenPipelinePlanReadsBackToTheSameJson) {
    for (const char* name :
         {"prog_dis_all.cornell", "tc_rp.cornell", "sel_st.cornell_diffuse", "prog_tc.cornell", "sel_edge.cornell", "capict.cornell"}) {
        json j = golden(name);
        Read r = read(j.dump(2));
        ASSERT_TRUE(r.plan && r.plan->pipeline) << name << ": " << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
        EXPECT_EQ(pipeline_plan_to_json(*r.plan->pipeline), j) << name;
    }
}

TEST(PlanReader, TypedValuesAreResolvedByTheCompiler) {
    Read r = read(golden("tc_rp.cornell").dump(2));
    ASSERT_TRUE(r.plan && r.plan->pipeline);
    const PipelinePlan& p = *r.plan->pipeline;
    ASSERT_TRUE(p.settings.budget);
    EXPECT_TRUE(p.settings.budget->percent);
    EXPECT_EQ(p.settings.budget->amount, 50);
    ASSERT_EQ(p.variables.size(), 2u);
    EXPECT_EQ(p.variables[1].variable, pipeline::SelectiveVariable::kSubsample);
    EXPECT_EQ(p.variables[1].from, 4);
    for (const PlanEdge* e : edges_into(p, "map.imp")) EXPECT_EQ(e->weight, 0.5);
    // The typed definitions the runtime evaluates.
    const PlanMap* imp = find_map(p, "map.imp");
    ASSERT_NE(imp, nullptr);
    EXPECT_EQ(imp->op, pipeline::GuidanceOperator::kImportance);
    EXPECT_EQ(imp->defines, "imp");
    EXPECT_EQ(imp->params.combine, "+");
    ASSERT_EQ(imp->inputs.size(), 2u);
    EXPECT_EQ(imp->inputs[0].node, "map.task");
    EXPECT_EQ(imp->inputs[0].weight, 0.5);
    const PlanMap* tm = find_map(p, "map.task");
    ASSERT_NE(tm, nullptr);
    EXPECT_NEAR(*tm->params.fovea, 2 * std::numbers::pi / 180, 1e-15);
}

// Every value of a plan replaced by each wrong type in turn: the reader either accepts the plan
// or reports one located E401 of its own, never a JSON library exception (type_error.302 was
// what `"version": "1"` gave) and never a crash.
TEST(PlanReader, AnyValueOfAnyTypeIsAcceptedOrALocatedE401) {
    const json plan = golden("prog_dis_all.cornell");
    const json flat = plan.flatten();
    const json replacements[] = {3, 2.5, -1, "x", nullptr, true, json::array(), json::object(), 1e300};
    size_t reads = 0, refused = 0;
    for (const auto& [pointer, _] : flat.items())
        for (const json& r : replacements) {
            json damaged = plan;
            damaged[json::json_pointer(pointer)] = r;
            Read result = read(damaged.dump(1));
            ++reads;
            if (result.plan) continue;
            ++refused;
            ASSERT_EQ(result.errors, 1u) << pointer << " = " << r.dump();
            EXPECT_EQ(result.diagnostics[0].code, "E401") << pointer;
            EXPECT_EQ(result.diagnostics[0].message.find("json.exception"), std::string::npos)
                << pointer << " = " << r.dump() << ": " << result.diagnostics[0].message;
            EXPECT_TRUE(result.diagnostics[0].span.valid()) << pointer;
        }
    EXPECT_GT(reads, 1000u);
    EXPECT_GT(refused, reads / 2);  // most damage is refused, not silently read
}

struct PlanDamage {
    const char* name;
    std::function<void(json&)> damage;
    const char* at;       // the plan text the error points at (its first characters)
    const char* message;  // part of the message
};

class PlanReaderDiagnostic : public ::testing::TestWithParam<PlanDamage> {};

TEST_P(PlanReaderDiagnostic, IsALocatedE401) {
    const PlanDamage& c = GetParam();
    json j = golden("prog_dis_all.cornell");
    c.damage(j);
    Read r = read(j.dump(2));
    EXPECT_FALSE(r.plan) << c.name;
    ASSERT_EQ(r.errors, 1u) << c.name;
    EXPECT_EQ(r.diagnostics[0].code, "E401") << c.name;
    EXPECT_NE(r.diagnostics[0].message.find(c.message), std::string::npos) << c.name << ": " << r.diagnostics[0].message;
    EXPECT_EQ(r.pointed_at(std::string(c.at).size()), c.at) << c.name << ": " << r.diagnostics[0].message;
    EXPECT_GT(r.file->position(r.diagnostics[0].span.begin).line, 0u);
}

INSTANTIATE_TEST_SUITE_P(
    EveryDamage, PlanReaderDiagnostic,
    ::testing::Values(
        PlanDamage{"version_as_text", [](json& j) { j["version"] = "1"; }, "\"1\"", "expected the integer 2"},
        PlanDamage{"old_version", [](json& j) { j["version"] = 1; }, "1", "this crex reads plan version 2"},
        PlanDamage{"component_as_number", [](json& j) { j["stages"]["preselective"]["children"][0]["children"][0]["children"][0]["component"] = 3; }, "3",
             "expected a component letter"},
        PlanDamage{"count_not_whole", [](json& j) {
                 j["stages"]["selective"] = {{"op", "seq"}, {"children", {{{"op", "repeat"}, {"count", 2.5},
                                                                          {"children", {{{"op", "exec"}, {"component", "T"}}}}}}}};
             }, "2.5", "a whole number"},
        PlanDamage{"no_nodes", [](json& j) { j["nodes"] = json::array(); j["edges"] = json::array(); j["variables"] = json::array(); },
             "[]", "no 'camera' node"},
        PlanDamage{"selective_node_missing", [](json& j) {
                 auto& n = j["nodes"];
                 for (size_t i = 0; i < n.size(); ++i)
                     if (n[i]["id"] == "selective") n.erase(i);
             }, "[", "no 'selective' node"},
        PlanDamage{"dangling_edge", [](json& j) { j["edges"][0]["to"] = "nowhere"; }, "\"nowhere\"", "no node 'nowhere'"},
        PlanDamage{"cycle", [](json& j) { j["edges"].push_back({{"from", "selective"}, {"to", "preselective"}, {"kind", "bin"}}); },
             "{", "closes a cycle"},
        PlanDamage{"duplicate_node", [](json& j) { j["nodes"][3]["id"] = "camera"; }, "\"camera\"", "defined twice"},
        PlanDamage{"node_param_unknown", [](json& j) { j["nodes"][3]["params"]["fovea"] = "2 deg"; }, "\"2 deg\"",
             "unknown node parameter 'fovea'"},
        PlanDamage{"crex_param_not_text", [](json& j) { j["nodes"][1]["params"]["crex"] = 7; }, "7", "expected the stage's crex"},
        PlanDamage{"spp_zero", [](json& j) { j["settings"]["spp"] = 0; }, "0", "whole number from 1 to 1048576"},
        PlanDamage{"lw_above_one", [](json& j) { j["settings"]["lw"] = 2; }, "2", "a number from 0 to 1"},
        PlanDamage{"ad_zero", [](json& j) { j["settings"]["ad"] = 0; }, "0", "whole number from 1 to 65536"},
        PlanDamage{"image_fraction", [](json& j) { j["settings"]["image"] = {{"width", 32.5}, {"height", 32}}; }, "32.5", "whole number"},
        PlanDamage{"budget_huge", [](json& j) { j["settings"]["budget"] = {{"seconds", 1e300}}; }, "1e+300", "a time in (0, 1e+06] s"},
        PlanDamage{"unknown_policy", [](json& j) { j["settings"]["policy"] = "nosuch"; }, "\"nosuch\"", "unknown scheduling policy"},
        PlanDamage{"unknown_setting", [](json& j) { j["settings"]["spp_max"] = 3; }, "3", "unknown setting 'spp_max'"},
        PlanDamage{"variable_out_of_range", [](json& j) { j["variables"][0]["to"] = 1e9; }, "1000000000", "in [1, 1048576] for spp"},
        PlanDamage{"variable_unknown", [](json& j) { j["variables"][0]["variable"] = "rays"; }, "\"rays\"", "unknown selective variable"},
        PlanDamage{"variable_component_not_subsample", [](json& j) { j["variables"][0]["component"] = "D"; }, "\"D\"", "only subsample takes one"},
        PlanDamage{"variable_component_unknown", [](json& j) { j["variables"][0]["component"] = "Q"; }, "\"Q\"", "'Q' is not a component"},
        PlanDamage{"refine_without_component", [](json& j) { j["variables"][0]["refine"] = 0.5; }, "0.5", "refine applies to one component"},
        PlanDamage{"modulation_unknown", [](json& j) { j["variables"][0]["modulation"] = "cubic"; }, "\"cubic\"", "unknown modulation function"},
        PlanDamage{"variable_map_dangling", [](json& j) { j["variables"][0]["map"] = "map.nosuch"; }, "\"map.nosuch\"", "no node 'map.nosuch'"},
        PlanDamage{"map_unknown_operator", [](json& j) { j["maps"][0]["operator"] = "salience"; }, "\"salience\"",
             "unknown guidance operator 'salience'"},
        PlanDamage{"map_input_dangling", [](json& j) { j["maps"][0]["inputs"][0]["node"] = "buffer.nosuch"; }, "\"buffer.nosuch\"",
             "not a map, a buffer or the preview"},
        PlanDamage{"map_depends_on_itself", [](json& j) { j["maps"][0]["inputs"][0]["node"] = j["maps"][0]["id"]; }, "\"map.sal\"",
             "depends on itself"},
        PlanDamage{"map_fovea_in_degrees", [](json& j) { j["maps"][0]["params"]["fovea"] = 200; }, "200", "radians in (0, pi)"},
        PlanDamage{"map_unknown_buffer", [](json& j) { j["buffers"][0]["buffer"] = "indirect"; }, "\"indirect\"", "unknown buffer"},
        PlanDamage{"negative_weight", [](json& j) { j["edges"].push_back({{"from", "map.sal"}, {"to", "map.dl"}, {"kind", "map"}, {"weight", -1}}); },
             "-1", "weight >= 0"}),
    [](const ::testing::TestParamInfo<PlanDamage>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(PlanReaderNesting, DeepJsonIsALocatedErrorInLinearMemory) {
    // 30,000 nested arrays used to take 955 MB (every pointer as long as its depth) and a
    // 20,000-deep tree crashed. Now the 65th level is E401 where it opens.
    std::string deep = "{\"version\": 2, \"x\": " + std::string(30000, '[') + std::string(30000, ']') + "}";
    Read r = read(deep);
    EXPECT_FALSE(r.plan);
    ASSERT_NE(r.find("E401"), nullptr);
    EXPECT_NE(r.find("E401")->message.find("nested more than 64 deep"), std::string::npos) << r.find("E401")->message;
    EXPECT_EQ(r.where("E401").col, 20u + 64);  // the 64th '[' after the 20 characters before them
}

}  // namespace
}  // namespace crex
