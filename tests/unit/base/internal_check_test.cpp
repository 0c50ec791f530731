// CREX_CHECK: an invariant that fails is an internal error naming its place, not user input.
#include <gtest/gtest.h>

#include "base/check.h"

namespace crex {
namespace {

TEST(InternalCheck, AFailedInvariantNamesItsFileAndLineAndAsksForAReport) {
    EXPECT_NO_THROW(CREX_CHECK(1 + 1 == 2));
    try {
        CREX_CHECK(1 + 1 == 3);
        FAIL() << "no throw";
    } catch (const InternalError& e) {
        std::string what = e.what();
        EXPECT_NE(what.find("internal error at "), std::string::npos) << what;
        EXPECT_NE(what.find("internal_check_test.cpp:"), std::string::npos) << what;
        EXPECT_NE(what.find("expected 1 + 1 == 3"), std::string::npos) << what;
        EXPECT_NE(what.find("please report"), std::string::npos) << what;
    }
}

TEST(InternalCheck, AFailedComparisonPrintsBothValues) {
    size_t rays = 3, samples = 4;
    EXPECT_NO_THROW(CREX_CHECK_LT(rays, samples));
    EXPECT_NO_THROW(CREX_CHECK_LE(rays, rays));
    EXPECT_NO_THROW(CREX_CHECK_NE(rays, samples));
    try {
        CREX_CHECK_EQ(rays, samples);
        FAIL() << "no throw";
    } catch (const InternalError& e) {
        EXPECT_NE(std::string(e.what()).find("expected rays == samples (3 vs 4)"), std::string::npos) << e.what();
    }
    int evaluated = 0;
    try {
        CREX_CHECK_LT(++evaluated + 1, 1);  // operands evaluated once, even when printed
        FAIL() << "no throw";
    } catch (const InternalError& e) {
        EXPECT_EQ(evaluated, 1);
        EXPECT_NE(std::string(e.what()).find("(2 vs 1)"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace crex
