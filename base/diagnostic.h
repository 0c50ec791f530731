/// \file diagnostic.h
/// Diagnostics (errors, warnings, notes) and the sink every pass reports into.
/// Codes come from diagnostic_codes.def, the single code table of the tool.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/source.h"

namespace crex {

enum class Severity { kError, kWarning, kNote };

std::string_view severity_name(Severity s);

/// A secondary location attached to a diagnostic ("the group opens here").
struct DiagnosticNote {
    SourceSpan span;
    std::string message;
};

struct Diagnostic {
    std::string code;  ///< "E004"; empty for internal errors
    Severity severity = Severity::kError;
    SourceSpan span;
    std::string message;
    std::vector<DiagnosticNote> notes;
    std::string help;  ///< a suggested fix, printed as "= help: ..."
    /// Where, as text, when there is no span to quote: a run's diagnostics point at positions
    /// the plan kept ("cornell.pipe:20:15"; the source text is gone by then), at an option, or
    /// at the command ("crex run"), or at a file (a texture that cannot be read).
    std::string where;
};

/// A diagnostic of the runtime: severity from the code table, placed by `where` (no span).
Diagnostic run_diagnostic(std::string_view code, std::string where, std::string message);

/// Entry of the code table.
struct DiagnosticCodeInfo {
    std::string_view code;
    Severity severity;
    std::string_view summary;
};

const std::vector<DiagnosticCodeInfo>& diagnostic_code_table();
std::optional<DiagnosticCodeInfo> find_diagnostic_code(std::string_view code);

/// Collects diagnostics from every pass. Keeps at most `limit` (a runaway input must not
/// produce a runaway report) but counts them all.
class DiagnosticSink {
public:
    explicit DiagnosticSink(size_t limit = 100) : limit_(limit) {}

    /// Report with the severity of the code table.
    Diagnostic& report(std::string_view code, SourceSpan span, std::string message);
    void add(Diagnostic d);

    size_t error_count() const { return errors_; }
    size_t warning_count() const { return warnings_; }
    bool has_errors() const { return errors_ > 0; }
    /// Number of diagnostics dropped because of the limit.
    size_t dropped() const { return dropped_; }

    /// Takes back every kept diagnostic with `code`: a later input made it moot (W305, a
    /// RADIANCE scene without a view, when `crex run --view` gives one).
    void withdraw(std::string_view code);

    /// Diagnostics sorted by (file, position, code), duplicates removed.
    std::vector<Diagnostic> sorted() const;
    const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }

private:
    size_t limit_;
    size_t errors_ = 0;
    size_t warnings_ = 0;
    size_t dropped_ = 0;
    std::vector<Diagnostic> diagnostics_;
    Diagnostic overflow_;  // target of report() once the limit is reached
};

}  // namespace crex
