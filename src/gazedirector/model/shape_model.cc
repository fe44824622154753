#include "gazedirector/model/shape_model.h"

#include <Eigen/Dense>

#include "gazedirector/io/obj_reader.h"
#include "gazedirector/util/error.h"

namespace gazedirector {

ShapeModel ShapeModel::Load(const std::filesystem::path& shape_dir, int modes) {
  const auto mean_rows = ReadNumberTable(shape_dir / "mesh_mean.txt");
  const auto component_rows = ReadNumberTable(shape_dir / "pca_components.txt");
  const auto std_rows = ReadNumberTable(shape_dir / "transformed_std.txt");
  std::vector<double> stddev;
  for (const auto& row : std_rows) stddev.insert(stddev.end(), row.begin(), row.end());

  const int n = static_cast<int>(mean_rows.size());
  if (n == 0 || static_cast<int>(component_rows.size()) != 3 * n || static_cast<int>(stddev.size()) < modes) {
    Fail(ExitCode::kAssets, "{}: inconsistent shape model ({} vertices, {} component rows, {} deviations)",
         shape_dir.string(), n, component_rows.size(), stddev.size());
  }
  ShapeModel model;
  model.mean_.resize(3, n);
  for (int i = 0; i < n; ++i) {
    if (mean_rows[i].size() != 3) Fail(ExitCode::kAssets, "{}: mesh_mean row {} is not x y z", shape_dir.string(), i);
    for (int k = 0; k < 3; ++k) model.mean_(k, i) = 1000.0 * mean_rows[i][k];
  }
  model.scaled_modes_.resize(3 * n, modes);
  model.stddev_mm_.resize(modes);
  for (int j = 0; j < modes; ++j) {
    model.stddev_mm_[j] = 1000.0 * stddev[j];
    for (int r = 0; r < 3 * n; ++r) {
      if (static_cast<int>(component_rows[r].size()) <= j) Fail(ExitCode::kAssets, "{}: too few PCA modes", shape_dir.string());
      model.scaled_modes_(r, j) = component_rows[r][j] * model.stddev_mm_[j];
    }
  }
  return model;
}

void ShapeModel::Evaluate(const double* beta, Eigen::Matrix3Xd& shape) const {
  shape.resize(3, mean_.cols());
  Eigen::Map<Eigen::VectorXd> flat(shape.data(), shape.size());
  flat = Eigen::Map<const Eigen::VectorXd>(mean_.data(), mean_.size()) +
         scaled_modes_ * Eigen::Map<const Eigen::VectorXd>(beta, num_modes());
}

Eigen::VectorXd ShapeModel::Project(const Eigen::Matrix3Xd& shape) const {
  const Eigen::Map<const Eigen::VectorXd> flat(shape.data(), shape.size());
  const Eigen::Map<const Eigen::VectorXd> mean(mean_.data(), mean_.size());
  return scaled_modes_.colPivHouseholderQr().solve(flat - mean);
}

}  // namespace gazedirector
