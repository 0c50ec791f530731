// The caption of a component's image in a run's report: its share of the final image's light.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "runtime/report/run_report.h"

namespace crex {
namespace {

TEST(LightShare, SaysTheShareToOneDecimalAndNothingWhenThereIsNoWhole) {
    EXPECT_EQ(light_share_note(1, 8), "12.5 % of the image's light");
    EXPECT_EQ(light_share_note(0, 8), "0.0 % of the image's light");
    EXPECT_EQ(light_share_note(8, 8), "100.0 % of the image's light");
    // A share that rounds to 0.0 but is not nothing says so.
    EXPECT_EQ(light_share_note(1e-4, 8), "under 0.1 % of the image's light");
    // No light in the final image, or a figure that is not a number: no caption rather than a
    // division by zero or "nan %".
    EXPECT_EQ(light_share_note(1, 0), "");
    EXPECT_EQ(light_share_note(std::numeric_limits<double>::quiet_NaN(), 8), "");
    EXPECT_EQ(light_share_note(1, std::numeric_limits<double>::infinity()), "");
}

}  // namespace
}  // namespace crex
