#include "gazedirector/model/subdivision.h"

#include <cmath>
#include <map>

#include "gazedirector/io/obj_reader.h"
#include "gazedirector/util/error.h"

namespace gazedirector {

Subdivision Subdivision::Load(const std::filesystem::path& dir, const std::string& name, int num_source_vertices) {
  const auto index_rows = ReadNumberTable(dir / ("new_v_idxs_" + name + ".txt"));
  const auto weight_rows = ReadNumberTable(dir / ("new_v_weights_" + name + ".txt"));
  const auto triangle_rows = ReadNumberTable(dir / ("new_tris_" + name + ".txt"));
  if (index_rows.size() != weight_rows.size() || index_rows.empty()) {
    Fail(ExitCode::kAssets, "{}: subdivision stencils of {} have mismatched rows", dir.string(), name);
  }
  Subdivision subdivision;
  subdivision.num_source_ = num_source_vertices;
  subdivision.num_vertices_ = static_cast<int>(index_rows.size());
  std::map<int, Group> groups;
  for (std::size_t r = 0; r < index_rows.size(); ++r) {
    if (index_rows[r].size() != weight_rows[r].size()) Fail(ExitCode::kAssets, "{}: stencil {} is malformed", dir.string(), r);
    std::vector<int> indices;
    std::vector<double> weights;
    double total = 0;
    for (std::size_t k = 0; k < index_rows[r].size(); ++k) {
      const double weight = weight_rows[r][k];
      if (weight == 0.0) continue;  // padding
      const int index = static_cast<int>(index_rows[r][k]);
      if (index < 0 || index >= num_source_vertices) Fail(ExitCode::kAssets, "{}: stencil index out of range", dir.string());
      indices.push_back(index);
      weights.push_back(weight);
      total += weight;
    }
    if (std::abs(total - 1.0) > 1e-4) Fail(ExitCode::kAssets, "{}: stencil {} weights sum to {}", dir.string(), r, total);
    Group& group = groups[static_cast<int>(indices.size())];
    group.terms = static_cast<int>(indices.size());
    group.rows.push_back(static_cast<int>(r));
    group.indices.insert(group.indices.end(), indices.begin(), indices.end());
    group.weights.insert(group.weights.end(), weights.begin(), weights.end());
  }
  for (auto& [terms, group] : groups) subdivision.groups_.push_back(std::move(group));
  std::vector<int> flat;
  for (const auto& row : triangle_rows) {
    for (double value : row) flat.push_back(static_cast<int>(value));
  }
  if (flat.size() % 3 != 0) Fail(ExitCode::kAssets, "{}: triangle list of {} is not a multiple of 3", dir.string(), name);
  for (std::size_t i = 0; i < flat.size(); i += 3) {
    subdivision.triangles_.emplace_back(flat[i], flat[i + 1], flat[i + 2]);
    if (subdivision.triangles_.back().maxCoeff() >= subdivision.num_vertices()) {
      Fail(ExitCode::kAssets, "{}: subdivided triangle index out of range", dir.string());
    }
  }
  return subdivision;
}

}  // namespace gazedirector
