#include "gazedirector/fit/initialization.h"

#include <Eigen/Dense>

#include "gazedirector/model/eye_region_topology.h"

namespace gazedirector {
namespace {

// dlib's landmark indices of each eye's inner and outer corner.
constexpr int kCornerLandmarks[2][2] = {{42, 45}, {39, 36}};

}  // namespace

std::array<Eigen::Vector3d, 2> ModelEyeCorners(const Parameters& phi, const EyeRegionModel& model, int eye) {
  const Eigen::Matrix3d to_head = EyeRegionModel::ModelToHead(eye);
  const Eigen::Vector3d centre = EyeRegionModel::EyeCentreInHead(phi, eye);
  const Eigen::Matrix3d rotation = phi.rotation();
  const auto& mean = model.shape_model().mean();
  return {rotation * (centre + to_head * mean.col(topology::kInnerCorner)) + phi.translation(),
          rotation * (centre + to_head * mean.col(topology::kOuterCorner)) + phi.translation()};
}

Parameters InitializeFromLandmarks(const Face& face, const Camera& camera, const EyeRegionModel& model) {
  Parameters phi;
  phi.set_rotation(face.pose.rotation);
  phi.interocular() = kAverageInterocularMm;
  // Start from the eyes of the mean face: 33 mm above and 95 mm in front of the
  // head origin (see assets/face); then fit the translation to the corners.
  Eigen::Vector3d translation = face.pose.rotation * Eigen::Vector3d(0, -33, -80) + face.pose.translation;
  for (int iteration = 0; iteration < 10; ++iteration) {
    phi.block<Block::kTranslation>() = translation;
    Eigen::Matrix<double, 8, 3> jacobian;
    Eigen::Matrix<double, 8, 1> residual;
    for (int eye = 0; eye < 2; ++eye) {
      const auto corners = ModelEyeCorners(phi, model, eye);
      for (int k = 0; k < 2; ++k) {
        const Eigen::Vector3d& p = corners[k];
        const int row = 4 * eye + 2 * k;
        residual.segment<2>(row) = camera.Project(p) - face.landmarks[kCornerLandmarks[eye][k]];
        // d(projection)/d(translation) = d(projection)/dp.
        jacobian.row(row) << camera.fx / p.z(), 0, -camera.fx * p.x() / (p.z() * p.z());
        jacobian.row(row + 1) << 0, camera.fy / p.z(), -camera.fy * p.y() / (p.z() * p.z());
      }
    }
    const Eigen::Vector3d step = (jacobian.transpose() * jacobian).ldlt().solve(jacobian.transpose() * residual);
    translation -= step;
    if (step.norm() < 1e-3) break;
  }
  phi.block<Block::kTranslation>() = translation;
  return phi;
}

}  // namespace gazedirector
