// Throughput of the crex front end: parse + check + lower, on the stdlib (thesis) expressions.
// Target (issue 2): at least 100 000 expressions per second on one core.
//   build/release/bench/crex_frontend_bench
#include <benchmark/benchmark.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "compiler/crex/compile.h"

namespace {

std::vector<std::string> stdlib_expressions() {
    std::ifstream in(CREX_STDLIB_CREX);
    std::vector<std::string> out;
    for (std::string line; std::getline(in, line);)
        if (!line.empty() && line[0] != '#') out.push_back(line);
    return out;
}

void BM_CompileStdlibExpressions(benchmark::State& state) {
    std::vector<std::string> exprs = stdlib_expressions();
    if (exprs.empty()) state.SkipWithError("no expressions in " CREX_STDLIB_CREX);
    size_t compiled = 0;
    for (auto _ : state) {
        for (const auto& e : exprs) {
            crex::SourceFile file("<expr>", e);
            crex::DiagnosticSink sink;
            auto c = crex::compile_crex(file, sink);
            benchmark::DoNotOptimize(c.program);
            ++compiled;
        }
    }
    state.SetItemsProcessed(static_cast<int64_t>(compiled));
}
BENCHMARK(BM_CompileStdlibExpressions);

// Nesting depth d: parsing must stay linear (full-LL prediction made this super-linear).
void BM_CompileNested(benchmark::State& state) {
    size_t depth = static_cast<size_t>(state.range(0));
    std::string e = std::string(depth, '(') + "TD" + std::string(depth, ')');
    for (auto _ : state) {
        crex::SourceFile file("<expr>", e);
        crex::DiagnosticSink sink;
        auto c = crex::compile_crex(file, sink);
        benchmark::DoNotOptimize(c.program);
    }
    state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_CompileNested)->RangeMultiplier(4)->Range(4, 256)->Complexity();

}  // namespace


// Planning the normative example of spec/pipeline.md section 6 end to end: parse, check,
// resolve `extends` (prog_dis_all from the stdlib), lower both crex, analyse against the census
// of the Cornell box, prune and emit JSON. Target (issue 5): under 5 ms.
#include "compiler/pipeline/check.h"
#include "compiler/pipeline/parse.h"
#include "compiler/pipeline/resolve.h"
#include "compiler/plan/plan_pipeline.h"
#include "runtime/scene/census.h"
#include "runtime/scene/load_scene.h"

namespace {

void BM_PlanNormativeExample(benchmark::State& state) {
    std::ifstream in(CREX_EXAMPLE_PIPELINE);
    std::stringstream text;
    text << in.rdbuf();
    crex::Census census = crex::take_census(*crex::builtin_scene("cornell"));
    for (auto _ : state) {
        crex::SourceFile file("cornell_prog.pipe", text.str());
        crex::DiagnosticSink sink;
        auto ast = crex::pipeline::parse_pipeline_file(file, sink);
        crex::pipeline::check_pipeline_file(*ast, sink);
        auto resolved = crex::pipeline::resolve_pipeline(*ast, "", sink);
        auto plan = crex::plan_pipeline(*resolved, census.spawnable, "builtin:cornell", "", sink);
        std::string json = crex::pipeline_plan_to_json(*plan).dump(2);
        benchmark::DoNotOptimize(json);
        if (sink.has_errors()) state.SkipWithError("the example does not plan");
    }
}
BENCHMARK(BM_PlanNormativeExample)->Unit(benchmark::kMicrosecond);

// A pipeline of n maps, all used (one importance() of every map, so the planner keeps them) or
// none used (W201 for each, the planner prunes them), through the whole front end: parse,
// check, resolve, plan. Must stay linear in n (issue 37: 32,000 maps took 22.7 s, checking
// scanned every map per map). Complexity() fits the exponent; compare the n = 25k and 100k rows.
std::string pipeline_of_maps(int64_t n, bool used) {
    std::string text = "pipeline many {\n  preselective { crex \"TT\" }\n  guidance {\n";
    for (int64_t i = 0; i < n; ++i) text += "    m" + std::to_string(i) + " = saliency(preview)\n";
    if (used) {
        text += "    all = importance(";
        for (int64_t i = 0; i < n; ++i) text += (i ? ", m" : "m") + std::to_string(i) + " 1";
        text += ")\n";
    }
    text += std::string("  }\n  selective { vary spp 1 .. 4 by ") + (used ? "all" : "m0") + " }\n}\n";
    return text;
}

void plan_maps(benchmark::State& state, bool used) {
    const std::string text = pipeline_of_maps(state.range(0), used);
    for (auto _ : state) {
        crex::SourceFile file("many.pipe", text);
        crex::DiagnosticSink sink;
        auto ast = crex::pipeline::parse_pipeline_file(file, sink);
        crex::pipeline::check_pipeline_file(*ast, sink);
        auto resolved = crex::pipeline::resolve_pipeline(*ast, "", sink);
        auto plan = crex::plan_pipeline(*resolved, std::nullopt, "", "", sink);
        benchmark::DoNotOptimize(plan);
        if (sink.has_errors()) state.SkipWithError("the pipeline does not plan");
    }
    state.SetComplexityN(state.range(0));
}
void BM_PlanUnusedMaps(benchmark::State& state) { plan_maps(state, false); }
void BM_PlanUsedMaps(benchmark::State& state) { plan_maps(state, true); }
BENCHMARK(BM_PlanUnusedMaps)->RangeMultiplier(2)->Range(25000, 100000)->Unit(benchmark::kMillisecond)->Complexity();
BENCHMARK(BM_PlanUsedMaps)->RangeMultiplier(2)->Range(25000, 100000)->Unit(benchmark::kMillisecond)->Complexity();

}  // namespace

BENCHMARK_MAIN();
