// spec/crex.md §6: every conformance example gives the stated result and code.
#include <gtest/gtest.h>

#include "tests/support/compile_helpers.h"

namespace crex {
namespace {

class ValidCrex : public ::testing::TestWithParam<const char*> {};

TEST_P(ValidCrex, HasNoErrorsAndLowers) {
    auto r = testing::check(GetParam());
    EXPECT_EQ(r.errors, 0u) << GetParam();
    EXPECT_TRUE(r.compiled.program.has_value()) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(SpecSection6, ValidCrex,
                         ::testing::Values("", "D", "TT", "(TRSGD)*", "TT{TTMRSGD}2", "TTM{RSGDTTRSG}",
                                           "T{RSGM}", "MT{TRSGD}3", "(TT[RS]G)*D", "(TTMRGD)*",
                                           "<DGS>G", "(DGS)G", "[T{RS}]2", " T T ( D ) "));

TEST(ValidCrex, CleanExamplesHaveNoWarningsEither) {
    for (const char* e : {"", "D", "TT", "(TRSGD)*", "TT{TTMRSGD}2", "T{RSGM}", "(TT[RS]G)*D", "<DGS>G"}) {
        auto r = testing::check(e);
        EXPECT_EQ(r.warnings, 0u) << e;
    }
}

TEST(ValidCrex, StarRepeatedGivesW101Only) {
    for (const char* e : {"(T*)2", "(T*)*"}) {
        auto r = testing::check(e);
        EXPECT_EQ(r.errors, 0u) << e;
        EXPECT_EQ(r.codes(), std::vector<std::string>{"W101"}) << e;
    }
}

struct InvalidCase {
    const char* crex;
    const char* code;
};

class InvalidCrex : public ::testing::TestWithParam<InvalidCase> {};

TEST_P(InvalidCrex, ReportsTheStatedCode) {
    auto r = testing::check(GetParam().crex);
    EXPECT_GE(r.errors, 1u);
    EXPECT_TRUE(r.has_code(GetParam().code)) << GetParam().crex;
    EXPECT_FALSE(r.compiled.program.has_value());
    // The stated code is the first error reported (no unrelated error masks it).
    for (const auto& d : r.diagnostics) {
        if (d.severity != Severity::kError) continue;
        EXPECT_EQ(d.code, GetParam().code) << GetParam().crex;
        break;
    }
}

INSTANTIATE_TEST_SUITE_P(SpecSection6, InvalidCrex,
                         ::testing::Values(InvalidCase{"X", "E001"}, InvalidCase{"d", "E001"},
                                           InvalidCase{"(DG", "E002"}, InvalidCase{"<DG)", "E002"},
                                           InvalidCase{"D0", "E003"}, InvalidCase{"D99999999999", "E003"},
                                           InvalidCase{"{D*}", "E004"}, InvalidCase{"[G*]", "E005"},
                                           InvalidCase{"{T{R}}", "E006"}, InvalidCase{"{[RS]}", "E007"},
                                           InvalidCase{"*D", "E008"}, InvalidCase{"(2)", "E008"},
                                           InvalidCase{"D2 3", "E009"}),
                         [](const ::testing::TestParamInfo<InvalidCase>& p) {
                             return std::string(p.param.code) + "_case" + std::to_string(p.index);
                         });

}  // namespace
}  // namespace crex
