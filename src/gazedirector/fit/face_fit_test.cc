#include "gazedirector/fit/face_fit.h"

#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "gazedirector/model/eye_region_model.h"

namespace gazedirector {
namespace {

constexpr double kDegree = M_PI / 180.0;

// A head 600 mm in front of the camera, facing it, both eyes parallel.
Parameters FrontalHead() {
  Parameters phi;
  phi.block<Block::kTranslation>() = Eigen::Vector3d(10, -20, 600);
  phi.vergence() = 0;
  return phi;
}

double AngleBetweenDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) / kDegree;
}

TEST(GazeAnglesTest, FollowOpenFacesSigns) {
  EXPECT_TRUE(GazeAngles({0, 0, -1}).isZero(1e-12));
  // Toward the image's right and down are positive, in radians.
  const Eigen::Vector2d right = GazeAngles({std::sin(12 * kDegree), 0, -std::cos(12 * kDegree)});
  EXPECT_NEAR(right.x(), 12 * kDegree, 1e-12);
  EXPECT_NEAR(right.y(), 0, 1e-12);
  const Eigen::Vector2d down = GazeAngles({0, std::sin(7 * kDegree), -std::cos(7 * kDegree)});
  EXPECT_NEAR(down.x(), 0, 1e-12);
  EXPECT_NEAR(down.y(), 7 * kDegree, 1e-12);
  // The length of the vector does not matter.
  EXPECT_TRUE(GazeAngles({0.3, -0.2, -2}).isApprox(GazeAngles({0.03, -0.02, -0.2}), 1e-12));
}

TEST(EyeGazesTest, AFrontalHeadLookingAheadLooksAtTheCamera) {
  const Parameters phi = FrontalHead();
  const std::array<EyeGaze, 2> eyes = EyeGazes(phi);
  for (const EyeGaze& eye : eyes) {
    EXPECT_TRUE(eye.gaze.isApprox(Eigen::Vector3d(0, 0, -1), 1e-12));
    EXPECT_DOUBLE_EQ(eye.pitch_deg, 0);
    EXPECT_DOUBLE_EQ(eye.yaw_deg, 0);
  }
  // The subject's left eye is on the image's right, each half the
  // interocular distance from the translation, which is their midpoint.
  EXPECT_NEAR((eyes[kLeftEye].centre - eyes[kRightEye].centre).norm(), phi.interocular(), 1e-9);
  EXPECT_NEAR(eyes[kLeftEye].centre.x() - phi.translation().x(), 0.5 * phi.interocular(), 1e-9);
  EXPECT_TRUE((0.5 * (eyes[kLeftEye].centre + eyes[kRightEye].centre)).isApprox(phi.translation(), 1e-12));
}

TEST(EyeGazesTest, YawTowardTheSubjectsLeftLooksToTheImagesRightAndPitchUpLooksUp) {
  Parameters phi = FrontalHead();
  phi.gaze_yaw() = 20;
  for (const EyeGaze& eye : EyeGazes(phi)) {
    EXPECT_NEAR(GazeAngles(eye.gaze).x(), 20 * kDegree, 1e-9);
    EXPECT_NEAR(eye.yaw_deg, 20, 1e-12);
  }
  phi.gaze_yaw() = 0;
  phi.gaze_pitch() = 15;
  for (const EyeGaze& eye : EyeGazes(phi)) {
    EXPECT_NEAR(GazeAngles(eye.gaze).y(), -15 * kDegree, 1e-9);  // OpenFace: down is positive
    EXPECT_NEAR(eye.pitch_deg, 15, 1e-12);
  }
}

TEST(EyeGazesTest, VergenceTurnsEachEyeTowardTheNose) {
  Parameters phi = FrontalHead();
  phi.vergence() = 6;
  const std::array<EyeGaze, 2> eyes = EyeGazes(phi);
  EXPECT_NEAR(eyes[kLeftEye].yaw_deg, -3, 1e-12);
  EXPECT_NEAR(eyes[kRightEye].yaw_deg, 3, 1e-12);
  EXPECT_LT(eyes[kLeftEye].gaze.x(), 0);  // the left eye, on the image's right, looks left
  EXPECT_GT(eyes[kRightEye].gaze.x(), 0);
  EXPECT_NEAR(AngleBetweenDeg(eyes[kLeftEye].gaze, eyes[kRightEye].gaze), 6, 1e-9);
}

TEST(EyeGazesTest, TheGazeTurnsWithTheHeadButItsAnglesStayTheHeads) {
  Parameters phi = FrontalHead();
  phi.gaze_pitch() = -10;
  phi.gaze_yaw() = 8;
  const std::array<EyeGaze, 2> unturned = EyeGazes(phi);
  phi.block<Block::kRotation>() = Eigen::Vector3d(5, 25, -3);
  const std::array<EyeGaze, 2> turned = EyeGazes(phi);
  const Eigen::Matrix3d rotation = phi.rotation();
  for (int eye = 0; eye < 2; ++eye) {
    EXPECT_TRUE(turned[eye].gaze.isApprox(rotation * unturned[eye].gaze, 1e-12));
    EXPECT_NEAR(turned[eye].gaze.norm(), 1, 1e-12);
    EXPECT_DOUBLE_EQ(turned[eye].pitch_deg, -10);
    EXPECT_DOUBLE_EQ(turned[eye].yaw_deg, 8);
    // The centres turn about the translation, the eyes' midpoint.
    const Eigen::Vector3d offset = unturned[eye].centre - phi.translation();
    EXPECT_TRUE((turned[eye].centre - phi.translation()).isApprox(rotation * offset, 1e-12));
  }
}

TEST(EyeGazesTest, EyesFixatingAPointHaveRaysThroughIt) {
  Parameters phi = FrontalHead();
  phi.block<Block::kRotation>() = Eigen::Vector3d(-4, 18, 2);
  // Straight ahead of the turned head and below its eyes, where both eyes
  // share one pitch (elsewhere the mean pitch misses by a little).
  const Eigen::Vector3d point = phi.rotation() * Eigen::Vector3d(0, 60, -450) + phi.translation();
  const Eigen::Vector3d angles = EyeRegionModel::FixationAngles(phi, point);
  phi.gaze_pitch() = angles.x();
  phi.gaze_yaw() = angles.y();
  phi.vergence() = angles.z();
  for (const EyeGaze& eye : EyeGazes(phi)) {
    const Eigen::Vector3d to_point = point - eye.centre;
    EXPECT_LT(AngleBetweenDeg(eye.gaze, to_point), 1e-6);
  }
}

}  // namespace
}  // namespace gazedirector
