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

}  // namespace
}  // namespace crex
