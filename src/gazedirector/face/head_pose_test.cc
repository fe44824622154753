#include "gazedirector/face/head_pose.h"

#include <cmath>
#include <cstdio>
#include <vector>

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

  for (HeadPoseMethod method : {HeadPoseMethod::kPerspectiveNPoint, HeadPoseMethod::kKabsch}) {
    const HeadPose pose = EstimateHeadPose(landmarks, mean_face, camera, nullptr, method);
    const char* name = method == HeadPoseMethod::kKabsch ? "Kabsch" : "perspective-n-point";
    EXPECT_LT((pose.translation - truth.translation).norm(), 1.0) << name;
    EXPECT_LT(Eigen::AngleAxisd(pose.rotation.transpose() * truth.rotation).angle(), DegToRad(0.2)) << name;
    EXPECT_LT(pose.reprojection_error_px, 0.01) << name;
  }
}

// The paper's Kabsch alignment and perspective-n-point read real faces'
// landmarks alike: the stills and the dlib group photos, every face found.
TEST(HeadPoseTest, KabschAndPerspectiveNPointAgreeOnRealFaces) {
  const MeanFace& mean_face = testing::SharedMeanFace();
  std::vector<double> angles, extra_px;
  for (const char* photo : {"images/d30.jpg", "images/s12.jpg", "images/s42.jpg", "images/d19.jpg", "images/d8.jpg",
                            "images/s39.jpg", "dlib-faces/2008_001009.jpg", "dlib-faces/2008_002506.jpg",
                            "dlib-faces/2009_004587.jpg", "dlib-faces/bald_guys.jpg"}) {
    const testing::DetectedStill still = testing::DetectStill(photo);
    for (const Face& face : still.faces) {
      const HeadPose pnp = EstimateHeadPose(face.landmarks, mean_face, still.camera);
      const HeadPose kabsch = EstimateHeadPose(face.landmarks, mean_face, still.camera, nullptr, HeadPoseMethod::kKabsch);
      const double angle = RadToDeg(Eigen::AngleAxisd(kabsch.rotation * pnp.rotation.transpose()).angle());
      std::printf("%s face %d: %.2f deg apart, %.2f mm, reprojection %.2f / %.2f px\n", photo, face.id, angle,
                  (kabsch.translation - pnp.translation).norm(), kabsch.reprojection_error_px, pnp.reprojection_error_px);
      angles.push_back(angle);
      extra_px.push_back(kabsch.reprojection_error_px - pnp.reprojection_error_px);
    }
  }
  ASSERT_GE(angles.size(), 30u);
  for (std::size_t i = 0; i < angles.size(); ++i) {
    EXPECT_LT(angles[i], 4.0) << i;  // measured: 0.2-2.7 deg
    EXPECT_GE(extra_px[i], -1e-6) << i << ": perspective-n-point minimises the pixels' error";
    EXPECT_LT(extra_px[i], 0.2) << i;  // measured: at most 0.13 px
  }
}

// Landmarks heaped on one pixel give the lines of sight no spread to place
// the face by; either method still returns numbers, not NaNs.
TEST(HeadPoseTest, HeapedLandmarksGiveAFinitePoseEitherWay) {
  Landmarks68 heaped;
  heaped.fill(Eigen::Vector2d(320, 240));
  const Camera camera = Camera::Default(640, 480);
  for (HeadPoseMethod method : {HeadPoseMethod::kPerspectiveNPoint, HeadPoseMethod::kKabsch}) {
    const HeadPose pose = EstimateHeadPose(heaped, testing::SharedMeanFace(), camera, nullptr, method);
    EXPECT_TRUE(pose.rotation.allFinite() && pose.translation.allFinite()) << static_cast<int>(method);
    EXPECT_TRUE(std::isfinite(pose.reprojection_error_px)) << static_cast<int>(method);
  }
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
