#include "gazedirector/face/face_detector.h"

#include <array>
#include <vector>

#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/opencv/cv_image.h>
#include <gtest/gtest.h>

#include "gazedirector/geometry/rotation.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

// The detector the build stored decoded must be dlib's own: the same windows
// with the same scores, down to the weak ones below the usual threshold.
TEST(FaceDetectorTest, TheStoredDetectorIsDlibsOwn) {
  dlib::frontal_face_detector reference = dlib::get_frontal_face_detector();
  FaceDetector detector;
  int windows = 0;
  for (const char* name : {"images/s42.jpg", "images/d8.jpg", "images/s39.jpg"}) {
    const cv::Mat gray = testing::GrayPhoto(name);
    std::vector<std::pair<double, dlib::rectangle>> theirs;
    reference(dlib::cv_image<unsigned char>(gray), theirs, -0.8);
    const std::vector<Detection> ours = detector.Detect(gray, 1.0, -0.8);
    ASSERT_EQ(ours.size(), theirs.size()) << name;
    for (std::size_t i = 0; i < ours.size(); ++i) {  // both best first
      EXPECT_NEAR(ours[i].score, theirs[i].first, 1e-9) << name;
      EXPECT_NEAR(ours[i].box.x, theirs[i].second.left(), 1e-9) << name;
      EXPECT_NEAR(ours[i].box.width, theirs[i].second.width(), 1e-9) << name;
    }
    windows += static_cast<int>(ours.size());
  }
  EXPECT_GE(windows, 3);
}

// The turned searches run side by side, each thread with its own detector;
// they must find what searching one roll at a time finds.
TEST(FaceDetectorTest, TurnedSearchesSideBySideFindWhatOneByOneFinds) {
  const cv::Mat gray = testing::TurnPhoto(testing::GrayPhoto("images/s12.jpg"), 90).image;
  const std::array<double, 4> rolls = {DegToRad(45.0), DegToRad(-45.0), DegToRad(90.0), DegToRad(-90.0)};
  FaceDetector together;
  const std::vector<std::vector<Detection>> found = together.DetectTurned(gray, rolls, 1.5);
  ASSERT_EQ(found.size(), rolls.size());
  int faces = 0;
  for (std::size_t r = 0; r < rolls.size(); ++r) {
    FaceDetector alone;
    const std::vector<Detection> expected = alone.DetectTurned(gray, std::span(&rolls[r], 1), 1.5).front();
    ASSERT_EQ(found[r].size(), expected.size()) << r;
    for (std::size_t i = 0; i < expected.size(); ++i) {
      EXPECT_DOUBLE_EQ(found[r][i].score, expected[i].score);
      EXPECT_DOUBLE_EQ(found[r][i].box.x, expected[i].box.x);
      EXPECT_DOUBLE_EQ(found[r][i].roll, expected[i].roll);
    }
    faces += static_cast<int>(expected.size());
  }
  EXPECT_GE(faces, 1) << "s12 turned a quarter is found by one of the turned searches";
}

}  // namespace
}  // namespace gazedirector
