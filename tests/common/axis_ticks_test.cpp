// Plot axes get round ticks: steps of 1, 2 or 5 times a power of ten that cover the data, labels
// no longer than the step needs, and decades on a log axis.

#include "common/axis_ticks.h"

#include <gtest/gtest.h>

#include <cmath>

namespace common {
namespace {

// True when `step` is 1, 2 or 5 times a power of ten (to round-off).
bool is_125(double step) {
  const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-12));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (std::abs(mantissa - m) < 1e-9) return true;
  return false;
}

TEST(AxisTicks, RoundUpTo125) {
  EXPECT_DOUBLE_EQ(round_up_to_125(0.0571), 0.1);
  EXPECT_DOUBLE_EQ(round_up_to_125(0.2), 0.2);
  EXPECT_DOUBLE_EQ(round_up_to_125(3), 5);
  EXPECT_DOUBLE_EQ(round_up_to_125(7.5), 10);
  EXPECT_DOUBLE_EQ(round_up_to_125(1200), 2000);
}

TEST(AxisTicks, LinearTicksAreRoundAndCoverTheData) {
  // Ranges like the spill plot's (an area of 0.0456 to 0.285625 m^2, a time of 3 to 12 s).
  const double ranges[][2] = {{0.0456, 0.285625}, {3, 12}, {0, 7.31}, {-0.013, 0.0021},
                              {1234, 98765},      {5, 5},  {0, 0}};
  for (const auto& r : ranges) {
    const AxisTicks t = linear_ticks(r[0], r[1]);
    SCOPED_TRACE(std::to_string(r[0]) + " .. " + std::to_string(r[1]));
    EXPECT_TRUE(is_125(t.step)) << t.step;
    EXPECT_LE(t.lo, r[0]);
    EXPECT_GE(t.hi, r[1]);
    EXPECT_GT(t.hi, t.lo);
    ASSERT_GE(t.values.size(), 3u);
    EXPECT_LE(t.values.size(), 12u);
    ASSERT_EQ(t.values.size(), t.labels.size());
    for (size_t k = 0; k < t.values.size(); ++k) {
      // Every tick a whole number of steps, and its label reads back as its value.
      EXPECT_NEAR(t.values[k] / t.step, std::round(t.values[k] / t.step), 1e-6);
      EXPECT_NEAR(std::stod(t.labels[k]), t.values[k], 1e-6 * t.step) << t.labels[k];
      EXPECT_LE(t.labels[k].size(), 7u) << t.labels[k];
    }
  }
}

TEST(AxisTicks, LabelsUseTheStepsDecimals) {
  EXPECT_EQ(tick_label(0.25, 0.05), "0.25");
  EXPECT_EQ(tick_label(0.3, 0.1), "0.3");
  EXPECT_EQ(tick_label(12, 2), "12");
  EXPECT_EQ(tick_label(-1e-17, 0.1), "0.0");
  EXPECT_EQ(linear_ticks(0.0456, 0.285625).labels.front(), "0.00");
}

TEST(AxisTicks, LogTicksAreDecades) {
  const AxisTicks t = log_ticks(std::log10(3e-5), std::log10(0.2));
  EXPECT_DOUBLE_EQ(t.lo, -5);
  EXPECT_DOUBLE_EQ(t.hi, 0);
  ASSERT_EQ(t.labels.size(), 6u);
  EXPECT_EQ(t.labels.front(), "1e-5");
  EXPECT_EQ(t.labels[3], "0.01");
  EXPECT_EQ(t.labels.back(), "1");
}

}  // namespace
}  // namespace common
