#include "gazedirector/face/head_pose.h"

#include <gtest/gtest.h>

#include "gazedirector/geometry/rotation.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

TEST(HeadPoseTest, RecoversThePoseOfAProjectedMeanFace) {
  const MeanFace& mean_face = testing::SharedMeanFace();
  const Camera camera = Camera::Default(640, 480);
  HeadPose truth;
  truth.rotation = RotationFromEulerXYZ({DegToRad(-10), DegToRad(25), DegToRad(5)});
  truth.translation = {30, -20, 650};
  Landmarks68 landmarks;
  for (int i = 0; i < kNumLandmarks; ++i) landmarks[i] = camera.Project(truth.rotation * mean_face[i] + truth.translation);

  const HeadPose pose = EstimateHeadPose(landmarks, mean_face, camera);
  EXPECT_LT((pose.translation - truth.translation).norm(), 1.0);
  EXPECT_LT(Eigen::AngleAxisd(pose.rotation.transpose() * truth.rotation).angle(), DegToRad(0.2));
  EXPECT_LT(pose.reprojection_error_px, 0.01);
}

TEST(HeadPoseTest, FrontalFaceHasIdentityRotationAndEulerRoundTrips) {
  const Eigen::Vector3d angles(0.3, -0.2, 0.1);
  EXPECT_LT((EulerXYZFromRotation(RotationFromEulerXYZ(angles)) - angles).norm(), 1e-12);
  const MeanFace& mean_face = testing::SharedMeanFace();
  // In the head frame the subject's left eye (42-47) is at +x and the brows above (-y) the eyes.
  EXPECT_GT(mean_face[45].x(), mean_face[36].x());
  EXPECT_LT(mean_face[19].y(), mean_face[37].y());
  EXPECT_LT(mean_face[30].z(), mean_face[36].z()) << "the nose tip is nearer the camera than the eye corners";
}

}  // namespace
}  // namespace gazedirector
