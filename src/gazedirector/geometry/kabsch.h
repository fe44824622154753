#pragma once

#include <Eigen/Core>

namespace gazedirector {

struct RigidTransform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

// Kabsch (1976): the proper rotation R and the translation t that minimise
// sum_i |R from_i + t - to_i|^2 over corresponding points (columns), at
// least three not on one line.
RigidTransform KabschAlign(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to);

}  // namespace gazedirector
