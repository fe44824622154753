#pragma once

#include <filesystem>

#include <Eigen/Core>

namespace gazedirector {

// The linear shape model of the facial eye region (the paper's M_geo):
// shape(β) = mean + Σ_j β_j σ_j u_j, with β in standard deviations. Vertices
// are in the model frame of the subject's left eye, in millimetres: origin at
// the eyeball centre, +x toward the outer corner, -y out of the face, +z up.
class ShapeModel {
 public:
  // Reads shape/mesh_mean.txt, pca_components.txt and transformed_std.txt,
  // keeping `modes` modes.
  static ShapeModel Load(const std::filesystem::path& shape_dir, int modes);

  int num_vertices() const { return static_cast<int>(mean_.cols()); }
  int num_modes() const { return static_cast<int>(scaled_modes_.cols()); }
  const Eigen::Matrix3Xd& mean() const { return mean_; }

  // Writes the shape for `beta` (num_modes() values) into `shape` (3 x n).
  void Evaluate(const double* beta, Eigen::Matrix3Xd& shape) const;

  // Least-squares coefficients (in standard deviations) of a shape.
  Eigen::VectorXd Project(const Eigen::Matrix3Xd& shape) const;

 private:
  Eigen::Matrix3Xd mean_;
  Eigen::MatrixXd scaled_modes_;  // 3n x modes: component j times σ_j, in mm
  Eigen::VectorXd stddev_mm_;
};

}  // namespace gazedirector
