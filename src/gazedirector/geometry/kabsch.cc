#include "gazedirector/geometry/kabsch.h"

#include <Eigen/LU>
#include <Eigen/SVD>

namespace gazedirector {

RigidTransform KabschAlign(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to) {
  const Eigen::Vector3d from_centre = from.rowwise().mean();
  const Eigen::Vector3d to_centre = to.rowwise().mean();
  const Eigen::Matrix3d covariance = (from.colwise() - from_centre) * (to.colwise() - to_centre).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  // A reflection fits mirrored point sets better; flipping the weakest axis keeps R a rotation.
  Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
  flip(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  RigidTransform transform;
  transform.rotation = svd.matrixV() * flip * svd.matrixU().transpose();
  transform.translation = to_centre - transform.rotation * from_centre;
  return transform;
}

}  // namespace gazedirector
