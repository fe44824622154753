#include "gazedirector/io/obj_reader.h"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "gazedirector/util/error.h"

namespace gazedirector {
namespace {

// A 1-based OBJ index as 0-based; none unless the text is a whole number.
std::optional<int> ObjIndex(const std::string& text) {
  int index = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), index);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return index - 1;
}

[[noreturn]] void Malformed(const std::filesystem::path& path, int line_number) {
  Fail(ExitCode::kAssets, "{}:{}: malformed record", path.string(), line_number);
}

}  // namespace

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
        const auto slash = corner.find('/');
        const std::optional<int> vertex = ObjIndex(corner.substr(0, slash));
        if (!vertex) Malformed(path, line_number);
        if (slash != std::string::npos && slash + 1 < corner.size() && corner[slash + 1] != '/') {
          const std::optional<int> uv = ObjIndex(corner.substr(slash + 1, corner.find('/', slash + 1) - slash - 1));
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
