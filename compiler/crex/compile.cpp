#include "compiler/crex/compile.h"

#include "compiler/crex/check.h"
#include "compiler/crex/parse.h"

namespace crex {

CompiledCrex compile_crex(const SourceFile& file, uint32_t begin, uint32_t end, DiagnosticSink& sink,
                          const LowerOptions& options) {
    CompiledCrex out;
    out.span = {&file, begin, end};
    size_t errors_before = sink.error_count();
    out.ast = parse_crex(file, begin, end, sink);
    if (!out.ast) return out;
    check_crex(*out.ast, sink);
    if (sink.error_count() == errors_before) out.program = lower_crex(*out.ast, options);
    return out;
}

CompiledCrex compile_crex(const SourceFile& file, DiagnosticSink& sink, const LowerOptions& options) {
    return compile_crex(file, 0, static_cast<uint32_t>(file.text().size()), sink, options);
}

std::vector<CompiledCrex> compile_crex_file(const SourceFile& file, DiagnosticSink& sink,
                                            const LowerOptions& options) {
    std::vector<CompiledCrex> out;
    for (uint32_t line = 1; line <= file.line_count(); ++line) {
        std::string_view text = file.line_text(line);
        size_t first = text.find_first_not_of(" \t\r\f\v");
        if (first == std::string_view::npos || text[first] == '#') continue;
        uint32_t begin = file.line_start(line);
        out.push_back(compile_crex(file, begin, begin + static_cast<uint32_t>(text.size()), sink, options));
    }
    return out;
}

}  // namespace crex
