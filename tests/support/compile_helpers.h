/// \file compile_helpers.h
/// Test helpers: compile a crex string and look at what came out.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "compiler/crex/compile.h"

namespace crex::testing {

struct CheckResult {
    std::unique_ptr<SourceFile> file;
    std::vector<Diagnostic> diagnostics;  // sorted
    CompiledCrex compiled;
    size_t errors = 0;
    size_t warnings = 0;

    bool has_code(const std::string& code) const {
        for (const auto& d : diagnostics)
            if (d.code == code) return true;
        return false;
    }
    std::vector<std::string> codes() const {
        std::vector<std::string> out;
        for (const auto& d : diagnostics) out.push_back(d.code);
        return out;
    }
};

inline CheckResult check(const std::string& text, const std::string& name = "<expr>") {
    CheckResult r;
    r.file = std::make_unique<SourceFile>(name, text);
    DiagnosticSink sink;
    r.compiled = compile_crex(*r.file, sink);
    r.diagnostics = sink.sorted();
    r.errors = sink.error_count();
    r.warnings = sink.warning_count();
    return r;
}

}  // namespace crex::testing
