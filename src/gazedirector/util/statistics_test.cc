#include "gazedirector/util/statistics.h"

#include <gtest/gtest.h>

namespace gazedirector {
namespace {

TEST(StatisticsTest, MedianQuantileAndMeanOfSmallSamples) {
  EXPECT_EQ(Median({}), 0);
  EXPECT_EQ(Median({4, 1, 3}), 3);
  EXPECT_EQ(Median({4, 1, 3, 2}), 2.5);  // the middle two's mean
  EXPECT_EQ(Mean({1, 2, 6}), 3);
  const std::vector<double> values = {10, 0, 30, 20};
  EXPECT_EQ(Quantile(values, 0.0), 0);
  EXPECT_EQ(Quantile(values, 1.0), 30);
  EXPECT_DOUBLE_EQ(Quantile(values, 0.5), Median(values));
  EXPECT_DOUBLE_EQ(Quantile(values, 0.25), 7.5);  // linear between 0 and 10
  const std::array<double, 3> quartiles = Quartiles(values);
  EXPECT_DOUBLE_EQ(quartiles[0], 7.5);
  EXPECT_DOUBLE_EQ(quartiles[1], 15);
  EXPECT_DOUBLE_EQ(quartiles[2], Quantile(values, 0.75));
  EXPECT_EQ(Quartiles({})[1], 0);
}

}  // namespace
}  // namespace gazedirector
