#include "gazedirector/video/gaze_tracker.h"

#include <gtest/gtest.h>

#include "gazedirector/io/video_reader.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

TEST(GazeTrackerTest, WarmStartsHoldSettledParametersAndStaySteady) {
  const auto model = EyeRegionModel::Load(testing::TestAssets());
  GazeTracker tracker(model, testing::SharedLandmarkDetector(), LoadMeanFace(testing::TestAssets().mean_face()));
  VideoReader reader(testing::DataPath("video/d3.mp4"));
  const Camera camera = Camera::Default(reader.info().width, reader.info().height);
  cv::Mat frame;
  std::vector<FaceFit> track;
  while (track.size() < 8 && reader.Read(frame)) {
    const std::vector<FaceFit> fits = tracker.ProcessFrame(frame, reader.timestamp_s(), camera);
    ASSERT_EQ(fits.size(), 1u);
    track.push_back(fits[0]);
  }
  EXPECT_FALSE(track[0].warm);
  const int settle = GazeTrackerOptions::Defaults().settle_frames;
  for (std::size_t i = 0; i < track.size(); ++i) {
    EXPECT_TRUE(track[i].fit.good) << i << ": " << track[i].fit.note;
    EXPECT_EQ(track[i].face.id, track[0].face.id);
    if (i >= 1) {
      EXPECT_TRUE(track[i].warm) << i;
    }
    if (i > static_cast<std::size_t>(settle)) {
      EXPECT_EQ(track[i].fit.phi.shape(), track[i - 1].fit.phi.shape()) << i;
      EXPECT_EQ(track[i].fit.phi.texture(), track[i - 1].fit.phi.texture()) << i;
    }
    if (i >= 1) {
      // A thirtieth of a second apart, the gaze moves by a few degrees at most.
      EXPECT_LT(std::abs(track[i].fit.phi.gaze_yaw() - track[i - 1].fit.phi.gaze_yaw()), 8.0) << i;
      EXPECT_LT(std::abs(track[i].fit.phi.gaze_pitch() - track[i - 1].fit.phi.gaze_pitch()), 8.0) << i;
    }
  }
}

}  // namespace
}  // namespace gazedirector
