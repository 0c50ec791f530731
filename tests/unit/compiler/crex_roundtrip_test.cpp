// Property tests over 10 000 random trees and 10 000 random byte strings.
#include <gtest/gtest.h>

#include <random>

#include "compiler/crex/compile.h"
#include "compiler/crex/parse.h"
#include "compiler/sched/print.h"
#include "tests/support/compile_helpers.h"
#include "tests/support/random_crex.h"

namespace crex {
namespace {

constexpr int kCases = 10000;

TEST(CrexRoundTrip, RandomTreesSurvivePrintAndParse) {
    testing::RandomCrex gen(20261121);
    for (int i = 0; i < kCases; ++i) {
        ast::Sequence tree = gen.sequence();
        std::string canonical = ast::print(tree);
        std::string spaced = gen.spaced_text(tree);

        auto a = testing::check(canonical);
        ASSERT_EQ(a.errors, 0u) << canonical;
        ASSERT_TRUE(a.compiled.ast.has_value());
        ASSERT_TRUE(ast::same_structure(a.compiled.ast->body, tree)) << canonical;

        auto b = testing::check(spaced);
        ASSERT_EQ(b.errors, 0u) << "[" << spaced << "]";
        ASSERT_TRUE(ast::same_structure(b.compiled.ast->body, tree)) << "[" << spaced << "]";

        // print(lower(x)) lowers back to the same schedule IR.
        const sched::Program& program = *a.compiled.program;
        std::string printed = sched::to_crex(program);
        auto c = testing::check(printed);
        ASSERT_EQ(c.errors, 0u) << canonical << " printed as " << printed;
        ASSERT_TRUE(sched::same_structure(*c.compiled.program, program))
            << canonical << " printed as " << printed << "\n"
            << sched::dump(program) << "---\n"
            << sched::dump(*c.compiled.program);
        // And printing is a fixed point.
        EXPECT_EQ(sched::to_crex(*c.compiled.program), printed);
    }
}

TEST(CrexRandomInput, RandomBytesNeverCrashAndEveryDiagnosticIsInsideTheText) {
    std::mt19937_64 rng(7);
    // Bias towards crex characters so that deep structures get exercised, but include
    // every byte value (NUL, invalid UTF-8, control characters).
    const std::string alphabet = "DGSTRMdx()<>{}[]*0123456789  \t\n";
    for (int i = 0; i < kCases; ++i) {
        size_t len = std::uniform_int_distribution<size_t>(0, 40)(rng);
        std::string s;
        for (size_t k = 0; k < len; ++k) {
            if (std::uniform_int_distribution<int>(0, 4)(rng) == 0)
                s += static_cast<char>(std::uniform_int_distribution<int>(0, 255)(rng));
            else
                s += alphabet[std::uniform_int_distribution<size_t>(0, alphabet.size() - 1)(rng)];
        }
        testing::CheckResult r;
        ASSERT_NO_THROW(r = testing::check(s)) << s;
        // The CLI's exit code is 1 exactly when there are errors, 0 otherwise.
        EXPECT_EQ(r.errors > 0, !r.compiled.program.has_value()) << s;
        for (const auto& d : r.diagnostics) {
            EXPECT_LE(d.span.begin, d.span.end);
            EXPECT_LE(d.span.end, s.size());
            EXPECT_FALSE(d.code.empty());
            EXPECT_TRUE(find_diagnostic_code(d.code).has_value()) << d.code;
        }
    }
}

}  // namespace
}  // namespace crex
