#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

#include <Eigen/Core>

namespace gazedirector {

// One step of Loop subdivision as precomputed stencils: each new vertex is a
// fixed weighted sum of source vertices (the assets' subdivision/ files).
class Subdivision {
 public:
  // Reads new_v_idxs_<name>.txt, new_v_weights_<name>.txt and new_tris_<name>.txt.
  static Subdivision Load(const std::filesystem::path& dir, const std::string& name, int num_source_vertices);

  int num_source_vertices() const { return num_source_; }
  int num_vertices() const { return num_vertices_; }
  const std::vector<Eigen::Vector3i>& triangles() const { return triangles_; }

  // out.col(r) = Σ_k w_rk source.col(i_rk); works for positions and uvs alike
  // (any column-major matrix with a fixed number of rows).
  template <typename Matrix>
  void Apply(const Matrix& source, Matrix& out) const {
    constexpr int kRows = Matrix::RowsAtCompileTime;
    static_assert(kRows > 0, "the number of rows must be fixed");
    out.resize(kRows, num_vertices());
    using Scalar = typename Matrix::Scalar;
    using Column = Eigen::Matrix<Scalar, kRows, 1>;
    for (const Group& group : groups_) {
      const int* index = group.indices.data();
      const double* weight = group.weights.data();
      for (int row : group.rows) {
        Column sum = Column::Zero();
        for (int k = 0; k < group.terms; ++k) {
          sum += static_cast<Scalar>(weight[k]) * Eigen::Map<const Column>(source.data() + static_cast<std::ptrdiff_t>(index[k]) * kRows);
        }
        Eigen::Map<Column>(out.data() + static_cast<std::ptrdiff_t>(row) * kRows) = sum;
        index += group.terms;
        weight += group.terms;
      }
    }
  }

 private:
  // Stencils with the same number of terms, stored together: each group's
  // inner loop then runs one length, which the branch predictor learns
  // (stencils of mixed lengths in turn mispredict most loop exits).
  struct Group {
    int terms = 0;
    std::vector<int> rows;        // the new vertices
    std::vector<int> indices;     // `terms` per row
    std::vector<double> weights;
  };

  int num_source_ = 0;
  int num_vertices_ = 0;
  std::vector<Group> groups_;
  std::vector<Eigen::Vector3i> triangles_;
};

}  // namespace gazedirector
