// libFuzzer target: any byte string through parse -> check -> lower -> print -> parse.
// Invariants: no crash, no sanitizer report, every span inside the input, errors exactly
// when no program comes out, and a lowered program prints to a crex that lowers back to it.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "compiler/crex/compile.h"
#include "compiler/sched/print.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    SourceFile file("<fuzz>", std::string(reinterpret_cast<const char*>(data), size));
    DiagnosticSink sink;
    CompiledCrex c = compile_crex(file, sink);
    for (const auto& d : sink.diagnostics())
        if (d.span.end > size || d.span.begin > d.span.end) std::abort();
    if (sink.has_errors() == c.program.has_value()) std::abort();
    if (c.program) {
        SourceFile again("<printed>", sched::to_crex(*c.program));
        DiagnosticSink sink2;
        CompiledCrex c2 = compile_crex(again, sink2);
        if (!c2.program || !sched::same_structure(*c2.program, *c.program)) std::abort();
    }
    return 0;
}
