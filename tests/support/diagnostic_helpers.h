/// \file diagnostic_helpers.h
/// What every diagnostics test looks at: the sorted diagnostics of one input, found by code,
/// and the check that one is where it should be and says what it should.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "base/diagnostic.h"

namespace crex::testing {

struct Diagnosed {
    std::vector<Diagnostic> diagnostics;
    size_t errors = 0;

    const Diagnostic* find(const std::string& code) const {
        for (const auto& d : diagnostics)
            if (d.code == code) return &d;
        return nullptr;
    }
    LineCol where(const std::string& code) const {
        const Diagnostic* d = find(code);
        return d && d->span.valid() ? d->span.file->position(d->span.begin) : LineCol{0, 0};
    }
};

/// One case of a table of refusals: an input, and the diagnostic it must give (where, and a
/// part of what it says).
struct DiagnosticCase {
    const char* name;
    const char* text;
    const char* code;
    uint32_t line;
    uint32_t col;
    const char* message_part;
};

/// `case_name` reports `code` at `line`:`col` (col 0: any column) with `message_part` in it.
inline void expect_diagnostic(const Diagnosed& r, const std::string& case_name, const std::string& code, size_t line, size_t col,
                              const std::string& message_part) {
    const Diagnostic* d = r.find(code);
    ASSERT_NE(d, nullptr) << case_name << ": expected " << code << ", got "
                          << (r.diagnostics.empty() ? "nothing" : r.diagnostics[0].code + " " + r.diagnostics[0].message);
    LineCol at = r.where(code);
    EXPECT_EQ(at.line, line) << case_name << ": " << d->message;
    if (col) {
        EXPECT_EQ(at.col, col) << case_name << ": " << d->message;
    }
    EXPECT_NE(d->message.find(message_part), std::string::npos) << case_name << ": " << d->message;
}

}  // namespace crex::testing
