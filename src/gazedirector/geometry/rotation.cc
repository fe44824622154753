#include "gazedirector/geometry/rotation.h"

#include <algorithm>
#include <cmath>

namespace gazedirector {

Eigen::Matrix3d RotationFromEulerXYZ(const Eigen::Vector3d& angles) {
  return (Eigen::AngleAxisd(angles.x(), Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(angles.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(angles.z(), Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

Eigen::Vector3d EulerXYZFromRotation(const Eigen::Matrix3d& r) {
  // R = Rx Ry Rz  =>  r(0,2) = sin(y), r(1,2) = -sin(x)cos(y), r(0,1) = -cos(y)sin(z).
  const double y = std::asin(std::clamp(r(0, 2), -1.0, 1.0));
  const double x = std::atan2(-r(1, 2), r(2, 2));
  const double z = std::atan2(-r(0, 1), r(0, 0));
  return {x, y, z};
}

Eigen::Matrix3d RotationFromAxisAngle(const Eigen::Vector3d& v) {
  const double angle = v.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
}

Eigen::Vector3d AxisAngleFromRotation(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd aa(rotation);
  return aa.axis() * aa.angle();
}

}  // namespace gazedirector
