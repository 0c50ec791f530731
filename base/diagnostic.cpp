#include "base/diagnostic.h"

#include <algorithm>
#include <tuple>

namespace crex {

std::string_view severity_name(Severity s) {
    switch (s) {
    case Severity::kError: return "error";
    case Severity::kWarning: return "warning";
    case Severity::kNote: return "note";
    }
    return "error";
}

const std::vector<DiagnosticCodeInfo>& diagnostic_code_table() {
    static const std::vector<DiagnosticCodeInfo> table = {
#define CREX_DIAGNOSTIC(code, severity, summary) {#code, Severity::severity, summary},
#include "base/diagnostic_codes.def"
#undef CREX_DIAGNOSTIC
    };
    return table;
}

std::optional<DiagnosticCodeInfo> find_diagnostic_code(std::string_view code) {
    for (const auto& info : diagnostic_code_table())
        if (info.code == code) return info;
    return std::nullopt;
}

Diagnostic run_diagnostic(std::string_view code, std::string where, std::string message) {
    Diagnostic d;
    d.code = std::string(code);
    auto info = find_diagnostic_code(code);
    d.severity = info ? info->severity : Severity::kError;
    d.where = std::move(where);
    d.message = std::move(message);
    return d;
}

Diagnostic& DiagnosticSink::report(std::string_view code, SourceSpan span, std::string message) {
    Diagnostic d = run_diagnostic(code, {}, std::move(message));
    d.span = span;
    add(std::move(d));
    if (diagnostics_.empty() || dropped_ > 0) {
        overflow_ = Diagnostic{};
        return overflow_;
    }
    return diagnostics_.back();
}

void DiagnosticSink::add(Diagnostic d) {
    if (d.severity == Severity::kError) ++errors_;
    if (d.severity == Severity::kWarning) ++warnings_;
    if (diagnostics_.size() >= limit_) {
        ++dropped_;
        return;
    }
    diagnostics_.push_back(std::move(d));
}

void DiagnosticSink::withdraw(std::string_view code) {
    std::erase_if(diagnostics_, [&](const Diagnostic& d) {
        if (d.code != code) return false;
        if (d.severity == Severity::kError) --errors_;
        if (d.severity == Severity::kWarning) --warnings_;
        return true;
    });
}

std::vector<Diagnostic> DiagnosticSink::sorted() const {
    std::vector<Diagnostic> out = diagnostics_;
    auto key = [](const Diagnostic& d) {
        return std::make_tuple(d.span.file ? d.span.file->name() : d.where, d.span.begin,
                               d.span.end, d.code, d.message);
    };
    std::stable_sort(out.begin(), out.end(),
                     [&](const Diagnostic& a, const Diagnostic& b) { return key(a) < key(b); });
    out.erase(std::unique(out.begin(), out.end(),
                          [&](const Diagnostic& a, const Diagnostic& b) { return key(a) == key(b); }),
              out.end());
    return out;
}

}  // namespace crex
