#include "gazedirector/face/eye_opening.h"

#include <gtest/gtest.h>

#include "gazedirector/face/face_tracker.h"
#include "gazedirector/io/video_reader.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

TEST(EyeOpeningTest, AspectRatioIsLidHeightOverEyeWidth) {
  Landmarks68 landmarks = ZeroLandmarks();
  // An eye 30 px wide whose lids are 6 and 12 px apart at the two thirds; the other 30 px wide and closed.
  const Eigen::Vector2d left[6] = {{0, 0}, {10, -3}, {20, -6}, {30, 0}, {20, 6}, {10, 3}};
  for (int k = 0; k < 6; ++k) {
    landmarks[36 + k] = left[k];
    landmarks[42 + k] = Eigen::Vector2d(100 + left[k].x(), 0);
  }
  EXPECT_DOUBLE_EQ(EyeAspectRatio(landmarks, 0), (6.0 + 12.0) / (2 * 30.0));
  EXPECT_DOUBLE_EQ(EyeAspectRatio(landmarks, 1), 0.0);
  EXPECT_DOUBLE_EQ(SmallerEyeAspectRatio(landmarks), 0.0);
  EXPECT_DOUBLE_EQ(EyeAspectRatio(ZeroLandmarks(), 0), 0.0);  // no eye: no division by zero
}

// d14.mp4 blinks at frames 16-21 (closed at 17-20).
TEST(EyeOpeningTest, TheLandmarksOfARealVideoSeeABlink) {
  FaceTracker faces = testing::MakeFaceTracker();
  VideoReader reader(testing::DataPath("video/d14.mp4"));
  const Camera camera = Camera::Default(reader.info().width, reader.info().height);
  EyeOpeningTracker opening;
  cv::Mat frame;
  for (int index = 0; index <= 26 && reader.Read(frame); ++index) {
    const std::vector<Face> found = faces.TrackFrame(frame, reader.timestamp_s(), camera);
    ASSERT_EQ(found.size(), 1u) << index;
    const double aspect_ratio = SmallerEyeAspectRatio(found[0].landmarks);
    const double fraction = opening.Update(aspect_ratio);
    if (index <= 15 || index >= 23) {
      EXPECT_GT(aspect_ratio, 0.25) << index;
      EXPECT_GT(fraction, 0.85) << index;
    }
    if (index >= 17 && index <= 20) {
      EXPECT_LT(aspect_ratio, 0.15) << index;
      EXPECT_LT(fraction, 0.45) << index;
    }
  }
  EXPECT_GT(opening.usual(), 0.3);
}

TEST(EyeOpeningTest, TheUsualOpeningRisesAtOnceAndSinksSlowly) {
  EyeOpeningTracker opening;
  EXPECT_DOUBLE_EQ(opening.Update(0.3), 1.0);
  EXPECT_DOUBLE_EQ(opening.Update(0.36), 1.0);
  EXPECT_NEAR(opening.Update(0.06), 0.06 / 0.354, 1e-9);  // a blink hardly moves it
  for (int i = 0; i < 200; ++i) opening.Update(0.2);      // eyes narrowed for seconds
  EXPECT_NEAR(opening.usual(), 0.2, 0.01);
}

}  // namespace
}  // namespace gazedirector
