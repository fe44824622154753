#include "gazedirector/fit/fit_options.h"

#include <gtest/gtest.h>

#include "gazedirector/util/error.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

ExitCode CodeOf(FitOptions& options, const std::string& assignment) {
  return testing::ExitCodeOf([&] { SetFitOption(options, assignment); });
}

TEST(FitOptionsTest, NumbersSetTheirOption) {
  FitOptions options;
  SetFitOption(options, "truncation=0.2");
  SetFitOption(options, "iterations=24");
  SetFitOption(options, "gaze_search=0");
  EXPECT_DOUBLE_EQ(options.weights.truncation, 0.2);
  EXPECT_EQ(options.max_iterations, 24);
  EXPECT_FALSE(options.gaze_search);
}

TEST(FitOptionsTest, PitchStartsTakeACommaSeparatedList) {
  FitOptions options;
  SetFitOption(options, "pitch_starts=-12.5,0,7");
  EXPECT_EQ(options.pitch_starts, (std::vector<double>{-12.5, 0, 7}));
  SetFitOption(options, "pitch_starts=3");
  EXPECT_EQ(options.pitch_starts, (std::vector<double>{3}));
}

TEST(FitOptionsTest, BadAssignmentsAreUsageErrorsThatChangeNothing) {
  FitOptions options;
  const FitOptions before = options;
  for (const std::string bad : {"truncation", "truncation=abc", "truncation=0.2x", "truncation=-1", "unknown=1",
                                "iterations=0", "pitch_starts=", "pitch_starts=1,,2", "pitch_starts=-10,50",
                                "pitch_starts=1;2", "truncation=nan", "shape_prior=inf", "iterations=nan",
                                "pitch_starts=nan"}) {
    EXPECT_EQ(CodeOf(options, bad), ExitCode::kUsage) << bad;
  }
  EXPECT_EQ(options.pitch_starts, before.pitch_starts);
  EXPECT_EQ(options.weights.truncation, before.weights.truncation);
  EXPECT_EQ(options.max_iterations, before.max_iterations);
}

TEST(FitOptionsTest, TheRecordNamesEveryOptionWithItsValue) {
  FitOptions options;
  SetFitOption(options, "truncation=0.2");
  SetFitOption(options, "pitch_starts=-5,5");
  SetFitOption(options, "hold_shape=1");
  const nlohmann::json record = FitOptionsToJson(options);
  for (const std::string& name : ListFitOptions()) EXPECT_TRUE(record.contains(name)) << name;
  EXPECT_EQ(record.size(), ListFitOptions().size());
  EXPECT_DOUBLE_EQ(record["truncation"].get<double>(), 0.2);
  EXPECT_EQ(record["pitch_starts"].get<std::vector<double>>(), (std::vector<double>{-5, 5}));
  EXPECT_TRUE(record["hold_shape"].get<bool>());
  EXPECT_FALSE(record["hold_rotation"].get<bool>());
  EXPECT_EQ(record["iterations"].get<int>(), FitOptions().max_iterations);
}

// Eye patches are fitted at their own working width unless told otherwise;
// later assignments win.
TEST(FitOptionsTest, EyePatchFitsStartFromTheirWorkingWidth) {
  EXPECT_EQ(EyePatchFitOptions({}).work_width, kEyePatchWorkWidth);
  EXPECT_NE(FitOptions().work_width, kEyePatchWorkWidth);
  const FitOptions options = EyePatchFitOptions({"iterations=5", "work_width=96", "iterations=7"});
  EXPECT_EQ(options.work_width, 96);
  EXPECT_EQ(options.max_iterations, 7);
}

// The crop's framing does not pull an eye patch's fit unless asked to.
TEST(FitOptionsTest, EyePatchFitsLeaveTheFramingLandmarkOutUnlessAsked) {
  EXPECT_EQ(EyePatchFitOptions({}).weights.landmarks, 0.0);
  EXPECT_GT(FitOptions().weights.landmarks, 0.0);
  EXPECT_EQ(EyePatchFitOptions({"landmarks=2"}).weights.landmarks, 2.0);
}

}  // namespace
}  // namespace gazedirector
