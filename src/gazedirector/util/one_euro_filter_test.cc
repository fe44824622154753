#include "gazedirector/util/one_euro_filter.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace gazedirector {
namespace {

// Values are in pixels of a face 100 px across (the speed unit), as the tracker uses it.
TEST(OneEuroFilterTest, RemovesJitterOfAStillSignal) {
  OneEuroFilter filter(1.0, 5.0);
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  double raw_change = 0, filtered_change = 0, previous_raw = 0, previous = 0;
  for (int i = 0; i < 300; ++i) {
    const double raw = 100 + noise(random);
    const double value = filter.Filter(raw, 1.0 / 30, 100.0);
    if (i > 30) raw_change += std::abs(raw - previous_raw), filtered_change += std::abs(value - previous);
    previous_raw = raw, previous = value;
  }
  EXPECT_LT(filtered_change, 0.3 * raw_change);
}

TEST(OneEuroFilterTest, FollowsFastMovesWithLittleLag) {
  OneEuroFilter adaptive(1.0, 5.0);
  OneEuroFilter fixed(1.0, 0.0);
  double adaptive_lag = 0, fixed_lag = 0;
  for (int i = 0; i < 30; ++i) {
    const double truth = 10.0 * i;  // 3 face widths per second
    adaptive_lag = truth - adaptive.Filter(truth, 1.0 / 30, 100.0);
    fixed_lag = truth - fixed.Filter(truth, 1.0 / 30, 100.0);
  }
  EXPECT_LT(adaptive_lag, 0.1 * fixed_lag);
}

}  // namespace
}  // namespace gazedirector
