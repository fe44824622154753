#include "gazedirector/geometry/kabsch.h"

#include <random>

#include <gtest/gtest.h>

#include "gazedirector/geometry/rotation.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

// The mean face's 68 landmarks (mm), the points the head pose aligns.
Eigen::Matrix3Xd MeanFacePoints() {
  const MeanFace& face = testing::SharedMeanFace();
  Eigen::Matrix3Xd points(3, kNumLandmarks);
  for (int i = 0; i < kNumLandmarks; ++i) points.col(i) = face[i];
  return points;
}

TEST(KabschTest, RecoversAKnownTurnAndShiftThroughNoise) {
  const Eigen::Matrix3Xd face = MeanFacePoints();
  const Eigen::Matrix3d turn = RotationFromEulerXYZ(Eigen::Vector3d(DegToRad(12), DegToRad(-35), DegToRad(6)));
  const Eigen::Vector3d shift(40, -25, 620);
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 1.0);  // mm, about a landmark's error
  Eigen::Matrix3Xd seen = (turn * face).colwise() + shift;
  for (int i = 0; i < seen.cols(); ++i) seen.col(i) += Eigen::Vector3d(noise(random), noise(random), noise(random));
  const RigidTransform found = KabschAlign(face, seen);
  const double angle_error = RadToDeg(Eigen::AngleAxisd(found.rotation * turn.transpose()).angle());
  EXPECT_LT(angle_error, 1.0) << "deg";
  EXPECT_LT((found.translation - shift).norm(), 3.0) << "mm";
  // Without noise, exactly.
  const RigidTransform exact = KabschAlign(face, (turn * face).colwise() + shift);
  EXPECT_LT((exact.rotation - turn).norm(), 1e-9);
  EXPECT_LT((exact.translation - shift).norm(), 1e-6);
}

TEST(KabschTest, AMirroredFaceStillGetsARotation) {
  const Eigen::Matrix3Xd face = MeanFacePoints();
  Eigen::Matrix3Xd mirrored = face;
  mirrored.row(0) *= -1;
  const RigidTransform found = KabschAlign(face, mirrored);
  EXPECT_NEAR(found.rotation.determinant(), 1.0, 1e-9);
  EXPECT_LT((found.rotation * found.rotation.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-9);
}

}  // namespace
}  // namespace gazedirector
