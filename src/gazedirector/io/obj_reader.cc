#include "gazedirector/io/obj_reader.h"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>

#include "gazedirector/util/error.h"

namespace gazedirector {
namespace {

// A 1-based OBJ index as 0-based; none unless the text is a whole number.
std::optional<int> ObjIndex(std::string_view text) {
  int index = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), index);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return index - 1;
}

[[noreturn]] void Malformed(const std::filesystem::path& path, int line_number) {
  Fail(ExitCode::kAssets, "{}:{}: malformed record", path.string(), line_number);
}

}  // namespace

Eigen::Matrix3Xd ObjMesh::PositionsMm() const {
  Eigen::Matrix3Xd mm(3, static_cast<Eigen::Index>(positions.size()));
  for (std::size_t i = 0; i < positions.size(); ++i) mm.col(static_cast<Eigen::Index>(i)) = 1000.0 * positions[i];
  return mm;
}

ObjMesh ReadObj(const std::filesystem::path& path) {
  std::ifstream stream(path);
  if (!stream) Fail(ExitCode::kAssets, "cannot read the mesh {}", path.string());
  ObjMesh mesh;
  std::string line;
  int line_number = 0;
  while (std::getline(stream, line)) {
    ++line_number;
    std::istringstream fields(line);
    std::string tag;
    fields >> tag;
    if (tag == "v") {
      Eigen::Vector3d p;
      if (!(fields >> p.x() >> p.y() >> p.z())) Malformed(path, line_number);
      mesh.positions.push_back(p);
    } else if (tag == "vt") {
      Eigen::Vector2d uv;
      if (!(fields >> uv.x() >> uv.y())) Malformed(path, line_number);
      mesh.uvs.push_back(uv);
    } else if (tag == "f") {
      std::vector<int> corners;
      std::string corner;
      while (fields >> corner) {
        // vertex, vertex/uv, vertex/uv/normal or vertex//normal
        const std::string_view text = corner;
        const auto slash = text.find('/');
        const std::optional<int> vertex = ObjIndex(text.substr(0, slash));
        if (!vertex) Malformed(path, line_number);
        const std::string_view after = slash == std::string_view::npos ? std::string_view() : text.substr(slash + 1);
        const std::string_view uv_text = after.substr(0, after.find('/'));
        if (!uv_text.empty()) {
          const std::optional<int> uv = ObjIndex(uv_text);
          if (!uv) Malformed(path, line_number);
          if (*uv != *vertex) Fail(ExitCode::kAssets, "{}:{}: uv index differs from vertex index", path.string(), line_number);
        }
        corners.push_back(*vertex);
      }
      if (corners.size() != 3) Fail(ExitCode::kAssets, "{}:{}: only triangles are supported", path.string(), line_number);
      mesh.triangles.emplace_back(corners[0], corners[1], corners[2]);
    }
  }
  const int count = static_cast<int>(mesh.positions.size());
  for (const auto& t : mesh.triangles) {
    if (t.minCoeff() < 0 || t.maxCoeff() >= count) Fail(ExitCode::kAssets, "{}: face index out of range", path.string());
  }
  if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size()) {
    Fail(ExitCode::kAssets, "{}: {} uvs for {} vertices", path.string(), mesh.uvs.size(), mesh.positions.size());
  }
  return mesh;
}

std::vector<std::vector<double>> ReadNumberTable(const std::filesystem::path& path) {
  std::ifstream stream(path);
  if (!stream) Fail(ExitCode::kAssets, "cannot read {}", path.string());
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(stream, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    std::vector<double> row;
    double value;
    while (fields >> value) row.push_back(value);
    if (!fields.eof()) Fail(ExitCode::kAssets, "{}: row {} is not numeric", path.string(), rows.size() + 1);
    if (!row.empty()) rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace gazedirector
