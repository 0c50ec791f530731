// `crex plan` and `crex check --scene` as a user runs them; every DOT goes through Graphviz.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "runtime/io/image_io.h"
#include "tests/support/crex_cli.h"

namespace crex {
namespace {

using testing::crex_cli;

TEST(CrexPlanCli, PrunesWhatTheDiffuseSceneCannotNeed) {
    auto r = crex_cli({"plan", "-e", "(TTMRSGD)*", "--scene", "builtin:cornell_diffuse"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("executes:      D*"), std::string::npos) << r.out;
    for (const char* c : {"pruned T at <expr>:1:2", "pruned M at <expr>:1:4", "pruned R at", "pruned S at", "pruned G at"})
        EXPECT_NE(r.out.find(c), std::string::npos) << c;
}

TEST(CrexPlanCli, JsonIsIdenticalAcrossRuns) {
    auto a = crex_cli({"plan", "-e", "TT{TTMRSGD}2", "--scene", "builtin:cornell", "--format", "json"});
    auto b = crex_cli({"plan", "-e", "TT{TTMRSGD}2", "--scene", "builtin:cornell", "--format", "json"});
    ASSERT_EQ(a.exit_code, 0);
    EXPECT_EQ(a.out, b.out);
    auto j = nlohmann::json::parse(a.out);
    EXPECT_EQ(j["scene"]["census_hash"], "d5579704575b1302");
}

TEST(CrexPlanCli, EveryDotRendersWithGraphviz) {
    auto dir = std::filesystem::temp_directory_path() / fmt::format("crex_plan_dot_{}", ::getpid());
    std::filesystem::create_directories(dir);
    int n = 0;
    for (const char* crex : {"", "D", "(TTMRSGD)*", "TT{TTMRSGD}2", "(TT[RS]G)*D", "<DGS>G", "[T{RS}]2", "{(TR)2}"})
        for (const char* scene : {"builtin:cornell", "builtin:cornell_diffuse"}) {
            auto dot = dir / fmt::format("p{}.dot", n++);
            auto r = crex_cli({"plan", "-e", crex, "--scene", scene, "--format", "dot", "-o", dot.string()});
            ASSERT_EQ(r.exit_code, 0) << crex << ": " << r.err;
            auto svg = testing::run_command({"/usr/bin/dot", "-Tsvg", dot.string(), "-o", (dir / "out.svg").string()});
            EXPECT_EQ(svg.exit_code, 0) << crex << " on " << scene << ": " << svg.err;
            EXPECT_GT(std::filesystem::file_size(dir / "out.svg"), 200u);
        }
    std::filesystem::remove_all(dir);
}

TEST(CrexPlanCli, CheckWithASceneWarnsW103AtTheStep) {
    auto r = crex_cli({"check", "--scene", "builtin:cornell_diffuse", "-e", "D{TD}"});
    EXPECT_EQ(r.exit_code, 0);  // warnings only
    EXPECT_NE(r.err.find("<expr>:1:3: warning[W103]: step T can never have work"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("<expr>:1:4: warning[W103]"), std::string::npos) << r.err;
}

TEST(CrexPlanCli, ErrorsAndExitCodes) {
    EXPECT_EQ(crex_cli({"plan", "-e", "{D*}"}).exit_code, 1);
    EXPECT_EQ(crex_cli({"plan", "-e", "D", "--scene", "/nonexistent.rad"}).exit_code, 3);
    EXPECT_EQ(crex_cli({"plan"}).exit_code, 2);
    EXPECT_EQ(crex_cli({"plan", "-e", "D", "--format", "pdf"}).exit_code, 2);  // svg and png are drawn (crex_outputs_cli_test)
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(CrexPlanCli, RunAcceptsAPlanAndRendersTheSameImage) {
    auto dir = std::filesystem::temp_directory_path() / fmt::format("crex_plan_run_{}", ::getpid());
    std::filesystem::create_directories(dir);
    std::string plan = (dir / "p.json").string();
    ASSERT_EQ(crex_cli({"plan", "-e", "(TTMRSGD)*", "--scene", "builtin:cornell", "--format", "json", "-o", plan}).exit_code, 0);
    auto a = crex_cli({"run", plan, "--size", "16x16", "--spp", "2", "-q", "-o", (dir / "a.exr").string()});
    auto b = crex_cli({"run", "-e", "(TTMRSGD)*", "--size", "16x16", "--spp", "2", "-q", "-o", (dir / "b.exr").string()});
    ASSERT_EQ(a.exit_code, 0) << a.err;
    ASSERT_EQ(b.exit_code, 0) << b.err;
    int w, h;
    std::vector<float> pa, pb;  // pixels, not bytes: EXR headers carry a timestamp
    ASSERT_EQ(read_image((dir / "a.exr").string(), w, h, pa), "");
    ASSERT_EQ(read_image((dir / "b.exr").string(), w, h, pb), "");
    EXPECT_EQ(pa, pb);

    // The plan names its scene's census: another scene is refused, never silently rendered.
    auto wrong = crex_cli({"run", plan, "--scene", "builtin:cornell_diffuse", "--size", "4x4", "-o", (dir / "c.exr").string()});
    EXPECT_EQ(wrong.exit_code, 1);
    EXPECT_NE(wrong.err.find("error[E402]"), std::string::npos) << wrong.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "c.exr"));

    // A damaged plan is a located error.
    std::ofstream(dir / "bad.json") << "{\"format\": \"crex-plan\", \"version\": 2,\n \"stages\": {\"preselective\": {\"op\": \"jump\"}}}";
    auto bad = crex_cli({"run", (dir / "bad.json").string(), "-o", (dir / "d.exr").string()});
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_NE(bad.err.find("bad.json:2:36: error[E401]"), std::string::npos) << bad.err;
    EXPECT_EQ(crex_cli({"run", plan, "-e", "D"}).exit_code, 2);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(CrexPlanCli, RunAPipelineAndItsPlanToTheSamePixels) {
    auto dir = std::filesystem::temp_directory_path() / fmt::format("crex_run_pipe_{}", ::getpid());
    std::filesystem::create_directories(dir);
    std::string pipe = (dir / "small.pipe").string();
    std::ofstream(pipe) << "pipeline small extends cbr {\n  scene \"builtin:cornell\"\n  image 16 x 12\n  budget 30 s\n"
                           "  preselective { spp 2 }\n  output { image \"" << (dir / "from_pipe.exr").string() << "\" }\n}\n";
    auto a = crex_cli({"run", pipe, "--format", "json"});
    ASSERT_EQ(a.exit_code, 0) << a.err;
    EXPECT_EQ(a.err.find("warning[W403]"), std::string::npos) << a.err;  // cbr executes fully now
    auto j = nlohmann::json::parse(a.out);
    EXPECT_EQ(j["size"], nlohmann::json::array({16, 12}));  // the pipeline's settings apply
    EXPECT_EQ(j["spp"], 2);
    EXPECT_EQ(j["budget_seconds"], 30);
    EXPECT_EQ(j["crex"], "TT{TTMRD}2");  // cbr's crex, S and G pruned for the Cornell box
    ASSERT_TRUE(std::filesystem::exists(dir / "from_pipe.exr"));

    std::string plan = (dir / "small.plan.json").string();
    ASSERT_EQ(crex_cli({"plan", pipe, "--format", "json", "-o", plan}).exit_code, 0);
    auto b = crex_cli({"run", plan, "-o", (dir / "from_plan.exr").string()});
    ASSERT_EQ(b.exit_code, 0) << b.err;
    int w, h;
    std::vector<float> pa, pb;
    ASSERT_EQ(read_image((dir / "from_pipe.exr").string(), w, h, pa), "");
    ASSERT_EQ(read_image((dir / "from_plan.exr").string(), w, h, pb), "");
    EXPECT_EQ(w, 16);
    EXPECT_EQ(pa, pb);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

// --dump-after resolve prints a pipeline without `extends` that plans exactly like the original.
TEST(CrexPlanCli, DumpAfterResolvePlansLikeTheOriginal) {
    auto dir = std::filesystem::temp_directory_path() / fmt::format("crex_plan_dump_{}", ::getpid());
    std::filesystem::create_directories(dir);
    for (const char* name : {"prog_dis_all", "sel_st", "tc_rp", "cbtcr_sel"}) {
        std::string pipe = std::string(CREX_SOURCE_DIR "/stdlib/pipelines/") + name + ".pipe";
        std::string flat = (dir / (std::string(name) + ".pipe")).string();
        auto resolved = crex_cli({"plan", pipe, "--dump-after", "resolve", "-o", flat});
        ASSERT_EQ(resolved.exit_code, 0) << name << ": " << resolved.err;
        auto a = crex_cli({"plan", pipe, "--scene", "builtin:cornell", "--format", "json"});
        auto b = crex_cli({"plan", flat, "--scene", "builtin:cornell", "--format", "json"});
        ASSERT_EQ(b.exit_code, 0) << name << ": " << b.err;
        auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
        for (const char* key : {"settings", "outputs", "maps", "buffers", "variables", "modulation_map", "nodes", "edges"})
            EXPECT_EQ(ja[key], jb[key]) << name << ": " << key;
        EXPECT_EQ(jb["pipeline"]["extends"], nlohmann::json::array({name})) << name;  // itself only: no bases left
    }
    std::filesystem::remove_all(dir);
}

TEST(CrexPlanCli, DumpAfterEachPass) {
    std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/prog_dis_all.pipe";
    auto parse = crex_cli({"plan", pipe, "--dump-after", "parse"});
    EXPECT_EQ(parse.exit_code, 0);
    EXPECT_NE(parse.out.find("pipeline prog_dis_all {"), std::string::npos) << parse.out;
    EXPECT_NE(parse.out.find("    ic = threshold(edges(component(D)), at 0.5)"), std::string::npos) << parse.out;
    auto compile = crex_cli({"plan", pipe, "--dump-after", "compile"});
    EXPECT_EQ(compile.exit_code, 0);
    EXPECT_NE(compile.out.find("preselective: (TTMRSGD)*"), std::string::npos) << compile.out;
    // plan keeps what prune removes for the diffuse box (its specular steps).
    auto plan = crex_cli({"plan", pipe, "--scene", "builtin:cornell_diffuse", "--dump-after", "plan"});
    auto pruned = crex_cli({"plan", pipe, "--scene", "builtin:cornell_diffuse", "--dump-after", "prune"});
    EXPECT_EQ(plan.out.find("pruned"), std::string::npos) << plan.out;
    EXPECT_NE(pruned.out.find("pruned"), std::string::npos) << pruned.out;
    // A pass after a failed check has nothing to print; parse still prints the file.
    auto dir = std::filesystem::temp_directory_path() / fmt::format("crex_plan_dump_bad_{}", ::getpid());
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "bad.pipe") << "pipeline p {\n  preselective { spp 0 }\n}\n";
    auto bad_parse = crex_cli({"plan", (dir / "bad.pipe").string(), "--dump-after", "parse"});
    EXPECT_EQ(bad_parse.exit_code, 1);
    EXPECT_NE(bad_parse.out.find("spp 0"), std::string::npos) << bad_parse.out;
    auto bad_check = crex_cli({"plan", (dir / "bad.pipe").string(), "--dump-after", "check"});
    EXPECT_EQ(bad_check.exit_code, 1);
    EXPECT_EQ(bad_check.out, "");
    EXPECT_NE(bad_check.err.find("bad.pipe:2:22: error[E203]"), std::string::npos) << bad_check.err;
    EXPECT_EQ(crex_cli({"plan", "-e", "TT", "--dump-after", "parse"}).exit_code, 2);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace crex
