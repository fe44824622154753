#pragma once

#include <filesystem>
#include <vector>

#include <Eigen/Core>

namespace gazedirector {

// A triangle mesh as stored in a Wavefront OBJ with one uv per vertex.
struct ObjMesh {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector2d> uvs;  // empty when the file has none
  std::vector<Eigen::Vector3i> triangles;

  // The positions as columns in millimetres, the model's unit (the assets'
  // meshes are in metres).
  Eigen::Matrix3Xd PositionsMm() const;
};

// Reads v / vt / f records (triangles only; a face's uv index must equal its
// vertex index, as in the eye-model assets). Fails with ExitCode::kAssets.
ObjMesh ReadObj(const std::filesystem::path& path);

// Reads a text matrix of numbers separated by spaces or commas.
std::vector<std::vector<double>> ReadNumberTable(const std::filesystem::path& path);

}  // namespace gazedirector
