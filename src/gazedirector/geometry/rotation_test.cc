#include "gazedirector/geometry/rotation.h"

#include <gtest/gtest.h>

namespace gazedirector {
namespace {

TEST(RotationTest, EulerAnglesFollowOpenFacesOrderAndRoundTrip) {
  const Eigen::Vector3d angles(0.3, -0.5, 0.2);
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(angles.x(), Eigen::Vector3d::UnitX()) *
                                    Eigen::AngleAxisd(angles.y(), Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(angles.z(), Eigen::Vector3d::UnitZ()))
                                       .toRotationMatrix();
  EXPECT_LT((RotationFromEulerXYZ(angles) - expected).norm(), 1e-12);
  EXPECT_LT((EulerXYZFromRotation(expected) - angles).norm(), 1e-12);
}

TEST(RotationTest, AxisAngleRoundTripsFromZeroToNearlyHalfATurn) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, -2, 0.5).normalized();
  for (double angle : {0.0, 1e-9, 0.4, 2.0, kPi - 1e-6}) {
    const Eigen::Vector3d axis_angle = angle * axis;
    const Eigen::Matrix3d rotation = RotationFromAxisAngle(axis_angle);
    EXPECT_LT((rotation - Eigen::AngleAxisd(angle, axis).toRotationMatrix()).norm(), 1e-9) << angle;
    EXPECT_LT((AxisAngleFromRotation(rotation) - axis_angle).norm(), 1e-6) << angle;
  }
  EXPECT_DOUBLE_EQ(RadToDeg(DegToRad(37.0)), 37.0);
}

}  // namespace
}  // namespace gazedirector
