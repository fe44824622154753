#include "gazedirector/eval/landmark_accuracy.h"

#include <gtest/gtest.h>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

TEST(LandmarkAccuracyTest, HandMarkedTestFacesAreFoundAndLandmarkedAccurately) {
  FaceTracker tracker = testing::MakeFaceTracker();
  const LandmarkAccuracy accuracy =
      EvaluateLandmarks(testing::DataPath("dlib-faces/testing_with_face_landmarks.xml"), tracker,
                        *testing::SharedLandmarkDetector());
  EXPECT_EQ(accuracy.faces, 25);
  EXPECT_GE(accuracy.detected, 24);
  // 300-W reports for this predictor are about 0.03-0.06 of the eye-corner distance.
  EXPECT_LT(accuracy.MeanGivenBox(), 0.04);
  EXPECT_LT(accuracy.MeanPipeline(), 0.04);
}

}  // namespace
}  // namespace gazedirector
