// libFuzzer target: any bytes as a pipeline file, through parse, check, resolve and plan (the
// path of `crex check` and `crex plan`). Invariants: no crash, hang or sanitizer report; spans
// inside the input; a plan only when there are no errors.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "compiler/pipeline/check.h"
#include "compiler/pipeline/parse.h"
#include "compiler/pipeline/resolve.h"
#include "compiler/plan/plan_pipeline.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    SourceFile f("fuzz.pipe", std::string(reinterpret_cast<const char*>(data), size));
    DiagnosticSink sink;
    auto ast = pipeline::parse_pipeline_file(f, sink);
    if (ast) pipeline::check_pipeline_file(*ast, sink);
    std::optional<PipelinePlan> plan;
    if (ast && !sink.has_errors())
        if (auto resolved = pipeline::resolve_pipeline(*ast, "", sink)) plan = plan_pipeline(*resolved, std::nullopt, "", "", sink);
    if (plan && sink.has_errors()) std::abort();
    for (const auto& d : sink.diagnostics())
        if (d.span.file == &f && (d.span.end > size || d.span.begin > d.span.end)) std::abort();
    if (plan) (void)pipeline_plan_to_json(*plan), (void)pipeline_plan_to_dot(*plan);
    return 0;
}
