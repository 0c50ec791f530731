// The name families of compiler/pipeline/registry.h: names are unique and round-trip through
// their enums, every one is documented, and stdlib pipeline names are the stdlib's files.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "compiler/pipeline/check.h"
#include "compiler/plan/pipeline_plan.h"
#include "compiler/pipeline/registry.h"
#include "compiler/pipeline/settings_table.h"
#include "compiler/pipeline/stdlib_pipelines.h"
#include "runtime/pipeline/svt.h"

namespace crex {
namespace {

using namespace crex::pipeline;

std::string docs() {
    std::ifstream in(CREX_SOURCE_DIR "/docs/pipeline-language.md");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

TEST(PipelineRegistry, EveryGuidanceOperatorRoundTripsAndIsDocumented) {
    std::string doc = docs();
    std::set<std::string_view> seen;
    for (const auto& o : kGuidanceOperators) {
        EXPECT_TRUE(seen.insert(o.name).second) << o.name;
        EXPECT_EQ(guidance_operator_from_name(o.name), o.op) << o.name;
        EXPECT_NE(doc.find("`" + std::string(o.name) + "("), std::string::npos) << o.name << " is not in docs/pipeline-language.md";
    }
    EXPECT_EQ(guidance_operator_names().size(), kGuidanceOperatorCount);
    EXPECT_FALSE(guidance_operator_from_name("salience"));
}

TEST(PipelineRegistry, EverySelectiveVariableAndModulationFunctionRoundTripsAndIsDocumented) {
    std::string doc = docs();
    for (const auto& v : kSelectiveVariables) {
        EXPECT_EQ(selective_variable_from_name(v.name), v.variable);
        EXPECT_LE(v.lo, v.hi);
        EXPECT_NE(doc.find("`" + std::string(v.name) + "`"), std::string::npos) << v.name;
    }
    for (size_t i = 0; i < kModulationFunctionCount; ++i) {
        auto f = static_cast<ModulationFunction>(i);
        EXPECT_EQ(modulation_function_from_name(name_of(f)), f);
        // Every modulation function maps [0, 1] onto [0, 1] with f(0) = 0 and f(1) = 1.
        EXPECT_DOUBLE_EQ(modulate(f, 0.0), 0.0) << name_of(f);
        EXPECT_DOUBLE_EQ(modulate(f, 1.0), 1.0) << name_of(f);
        EXPECT_NE(doc.find(std::string(name_of(f))), std::string::npos) << name_of(f);
    }
}

TEST(PipelineRegistry, StdlibPipelineNamesAreTheStdlibFiles) {
    const auto& names = stdlib_pipeline_names();
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(CREX_SOURCE_DIR "/stdlib/pipelines")) {
        if (e.path().extension() != ".pipe") continue;
        ++files;
        EXPECT_NE(std::find(names.begin(), names.end(), e.path().stem().string()), names.end()) << e.path();
    }
    EXPECT_GE(files, 16u);
    EXPECT_EQ(names.size(), files);  // every thesis renderer is a file (capict was the last)
}

// docs/plan.schema.json spells the registries' names out; they must be the same sets.
TEST(PipelineRegistry, PlanSchemaEnumsAreTheRegistryNames) {
    std::ifstream in(CREX_SOURCE_DIR "/docs/plan.schema.json");
    auto schema = nlohmann::json::parse(in);
    auto names = [](const nlohmann::json& e) {
        std::set<std::string> out;
        for (const auto& v : e) out.insert(v.get<std::string>());
        return out;
    };
    const auto& props = schema["properties"];
    std::set<std::string> ops, vars, fns, policies;
    for (const auto& o : kGuidanceOperators) ops.emplace(o.name);
    for (const auto& v : kSelectiveVariables) vars.emplace(v.name);
    for (auto f : kModulationFunctionNames) fns.emplace(f);
    for (auto p : scheduling_policy_names()) policies.emplace(p);
    EXPECT_EQ(names(props["maps"]["items"]["properties"]["operator"]["oneOf"][1]["enum"]), ops);
    EXPECT_EQ(names(props["variables"]["items"]["properties"]["variable"]["enum"]), vars);
    EXPECT_EQ(names(props["variables"]["items"]["properties"]["modulation"]["enum"]), fns);
    EXPECT_EQ(names(props["settings"]["properties"]["policy"]["enum"]), policies);
}

// Every setting a plan can hold is in the schema: a pipeline that set `ad` wrote a plan the
// schema refused (sel_quiet's), which no golden had shown.
TEST(PipelineRegistry, PlanSchemaHoldsEverySettingAPlanWrites) {
    std::ifstream in(CREX_SOURCE_DIR "/docs/plan.schema.json");
    const auto schema = nlohmann::json::parse(in);
    const auto& allowed = schema["properties"]["settings"]["properties"];
    PlanSettings all;
    all.width = 4, all.height = 4, all.selective_spp = 2, all.rounds = 2, all.seed = 1, all.lw = 0.01, all.av = 0.1, all.aa = 0.2;
    all.max_depth = 8, all.ab = 2, all.ad = 512, all.shadow_rays = 4, all.budget = PlanBudget{10, false, {}};
    all.policy = SchedulingPolicy::kTasks, all.reference = "ref.exr";
    const nlohmann::json written = plan_settings_to_json(all);
    EXPECT_EQ(written.size(), 15u);  // every field: a new one must be added here and to the schema
    for (const auto& [key, value] : written.items()) EXPECT_TRUE(allowed.contains(key)) << key << " is not in docs/plan.schema.json";
}

TEST(SettingsTable, RangesMatchTheFlagsOfCrexRun) {
    // The CLI's ranges (apps/crex/cmd_run.cpp): --spp 1..2^20, --lw 0..1, --max-depth 0..65535,
    // --ab 1..64, --ad 1..65536, --aa 1e-3..1, --ambient 0..1e30, --shadow-rays 1..1024.
    struct Want { const char* section; const char* name; double lo, hi; };
    for (const Want& w : {Want{"preselective", "spp", 1, 1 << 20}, Want{"", "lw", 0, 1}, Want{"", "max_depth", 0, 65535},
                          Want{"", "ab", 1, 64}, Want{"", "ad", 1, 65536}, Want{"", "aa", 1e-3, 1}, Want{"", "av", 0, 1e30},
                          Want{"preselective", "shadow_rays", 1, 1024}}) {
        const SettingRule* r = find_setting_rule(w.section, w.name);
        ASSERT_NE(r, nullptr) << w.name;
        EXPECT_EQ(r->lo, w.lo) << w.name;
        EXPECT_EQ(r->hi, w.hi) << w.name;
        EXPECT_EQ(setting_range_error(*r, w.lo), "") << w.name;
        EXPECT_NE(setting_range_error(*r, w.hi * 2 + 1), "") << w.name;
    }
    const SettingRule* spp = find_setting_rule("selective", "spp");
    ASSERT_NE(spp, nullptr);
    EXPECT_NE(setting_range_error(*spp, 2.5), "");
    EXPECT_NE(setting_range_error(*spp, std::numeric_limits<double>::quiet_NaN()), "");
    EXPECT_EQ(scheduling_policy_from_name("queues"), SchedulingPolicy::kQueues);
    EXPECT_FALSE(scheduling_policy_from_name("nosuch"));
}

}  // namespace
}  // namespace crex
