// libFuzzer target: any bytes as a kept plan (`crex run plan.json`). Invariants: no crash or
// sanitizer report and no exception (every damage is a located E401); spans inside the input.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "compiler/plan/read_plan.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    SourceFile f("fuzz.plan.json", std::string(reinterpret_cast<const char*>(data), size));
    DiagnosticSink sink;
    std::optional<CrexPlan> plan = read_plan(f, sink);
    if (plan.has_value() == sink.has_errors()) std::abort();
    for (const auto& d : sink.diagnostics())
        if (d.span.file == &f && (d.span.end > size || d.span.begin > d.span.end)) std::abort();
    return 0;
}
