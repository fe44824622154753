#include "gazedirector/fit/initialization.h"

#include <Eigen/Dense>

#include "gazedirector/model/eye_region_topology.h"

namespace gazedirector {
std::array<Eigen::Vector3d, 2> ModelEyeCorners(const Parameters& phi, const EyeRegionModel& model, int eye) {
  const Eigen::Matrix3d to_head = EyeRegionModel::ModelToHead(eye);
  const Eigen::Vector3d centre = EyeRegionModel::EyeCentreInHead(phi, eye);
  const Eigen::Matrix3d rotation = phi.rotation();
  const auto& mean = model.shape_model().mean();
  const Eigen::Vector3d inner = (1 - topology::kInnerCanthusWeightB) * mean.col(topology::kInnerCanthusA) +
                                topology::kInnerCanthusWeightB * mean.col(topology::kInnerCanthusB);
  return {rotation * (centre + to_head * inner) + phi.translation(),
          rotation * (centre + to_head * mean.col(topology::kOuterCanthus)) + phi.translation()};
}

Eigen::Vector3d FitTranslationToCorners(const Parameters& start, const EyeRegionModel& model, const Camera& camera,
                                        const std::vector<CornerTarget>& targets) {
  Parameters phi = start;
  Eigen::Vector3d translation = phi.translation();
  for (int iteration = 0; iteration < 10; ++iteration) {
    phi.block<Block::kTranslation>() = translation;
    Eigen::MatrixXd jacobian(2 * targets.size(), 3);
    Eigen::VectorXd residual(2 * targets.size());
    for (std::size_t k = 0; k < targets.size(); ++k) {
      const Eigen::Vector3d p = ModelEyeCorners(phi, model, targets[k].eye)[targets[k].corner];
      const Eigen::Index row = static_cast<Eigen::Index>(2 * k);
      residual.segment<2>(row) = camera.Project(p) - targets[k].pixel;
      // The projection's derivative with respect to the point is its derivative with respect to the translation.
      jacobian.row(row) << camera.fx / p.z(), 0, -camera.fx * p.x() / (p.z() * p.z());
      jacobian.row(row + 1) << 0, camera.fy / p.z(), -camera.fy * p.y() / (p.z() * p.z());
    }
    const Eigen::Vector3d step = (jacobian.transpose() * jacobian).ldlt().solve(jacobian.transpose() * residual);
    translation -= step;
    if (!translation.allFinite() || translation.z() <= 1.0) return start.translation();
    if (step.norm() < 1e-3) break;
  }
  return translation;
}

Parameters InitializeFromLandmarks(const Face& face, const Camera& camera, const EyeRegionModel& model) {
  Parameters phi;
  phi.set_rotation(face.pose.rotation);
  phi.interocular() = kAverageInterocularMm;
  // Start from the eyes of the mean face, about 33 mm above and 80 mm in
  // front of its origin (see assets/face); then fit the corners.
  phi.block<Block::kTranslation>() = face.pose.rotation * Eigen::Vector3d(0, -33, -80) + face.pose.translation;
  std::vector<CornerTarget> targets;
  for (int eye = 0; eye < 2; ++eye) {
    for (int corner = 0; corner < 2; ++corner) targets.push_back({eye, corner, face.landmarks[kCornerLandmarks[eye][corner]]});
  }
  phi.block<Block::kTranslation>() = FitTranslationToCorners(phi, model, camera, targets);
  return phi;
}

}  // namespace gazedirector
