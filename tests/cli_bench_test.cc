// End-to-end tests of `gazedirector bench`: what it prints, not how fast.
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::RunCli;

TEST(CliBenchTest, JsonGivesEachFigureItsMedianAndItsRuns) {
  std::string output;
  ASSERT_EQ(RunCli("bench --only renders_per_s --repeats 3 --json", &output), 0) << output;
  const nlohmann::json result = nlohmann::json::parse(output.substr(output.find('{')));
  const double median = result["renders_per_s"].get<double>();
  const std::vector<double> runs = result["runs"]["renders_per_s"].get<std::vector<double>>();
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_GT(median, 0);
  std::vector<double> sorted = runs;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_DOUBLE_EQ(median, sorted[1]);
  EXPECT_FALSE(result.contains("fit_fps"));  // only what was asked for
}

TEST(CliBenchTest, AnUnknownFigureIsAUsageError) {
  std::string output;
  EXPECT_EQ(RunCli("bench --only renders_per_second", &output), 2) << output;
  EXPECT_NE(output.find("unknown figure 'renders_per_second'"), std::string::npos) << output;
}

}  // namespace
}  // namespace gazedirector
