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

BENCHMARK_MAIN();
