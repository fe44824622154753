#include "gazedirector/face/landmark_detector.h"

#include <dlib/image_processing.h>
#include <dlib/opencv/cv_image.h>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "gazedirector/face/face_detector.h"
#include "gazedirector/io/image_io.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

// The sub-pixel evaluation must agree with dlib's own predictor, which rounds
// the same positions to whole pixels.
TEST(LandmarkDetectorTest, AgreesWithDlibsRoundedPredictor) {
  dlib::shape_predictor reference;
  dlib::deserialize(testing::TestAssets().landmark_model().string()) >> reference;
  const auto detector = testing::SharedLandmarkDetector();
  FaceDetector face_detector;
  int faces = 0;
  for (const char* name : {"images/s42.jpg", "images/d30.jpg", "images/d19.jpg"}) {
    cv::Mat gray;
    cv::cvtColor(ReadImage(testing::DataPath(name)), gray, cv::COLOR_BGR2GRAY);
    for (const Detection& detection : face_detector.Detect(gray)) {
      const Landmarks68 ours = detector->Detect(gray, detection.box);
      const dlib::rectangle rect(std::lround(detection.box.x), std::lround(detection.box.y),
                                 std::lround(detection.box.x + detection.box.width - 1),
                                 std::lround(detection.box.y + detection.box.height - 1));
      const dlib::full_object_detection theirs = reference(dlib::cv_image<unsigned char>(gray), rect);
      double fractional = 0;
      for (int i = 0; i < kNumLandmarks; ++i) {
        EXPECT_NEAR(ours[i].x(), theirs.part(i).x(), 0.5 + 1e-3) << name << " point " << i;
        EXPECT_NEAR(ours[i].y(), theirs.part(i).y(), 0.5 + 1e-3) << name << " point " << i;
        fractional += std::abs(ours[i].x() - std::round(ours[i].x()));
      }
      EXPECT_GT(fractional, 1.0) << "positions keep their sub-pixel part";
      ++faces;
    }
  }
  EXPECT_EQ(faces, 3);
}

}  // namespace
}  // namespace gazedirector
