#include "gazedirector/face/mean_face.h"

#include <fstream>

#include <nlohmann/json.hpp>

#include "gazedirector/io/json_format.h"
#include "gazedirector/util/error.h"

namespace gazedirector {

MeanFace LoadMeanFace(const std::filesystem::path& path) {
  std::ifstream stream(path);
  if (!stream) Fail(ExitCode::kAssets, "cannot read the mean face {}", path.string());
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(stream);
  } catch (const nlohmann::json::exception& e) {
    Fail(ExitCode::kAssets, "{}: invalid JSON ({})", path.string(), JsonErrorText(e));
  }
  MeanFace face;
  try {
    const nlohmann::json& points = document.at("points");
    if (!points.is_array() || points.size() != kNumLandmarks) {
      Fail(ExitCode::kAssets, "{}: expected {} points", path.string(), kNumLandmarks);
    }
    for (int i = 0; i < kNumLandmarks; ++i) {
      const nlohmann::json& p = points[i];
      if (!p.is_array() || p.size() != 3) Fail(ExitCode::kAssets, "{}: point {} is not x, y, z", path.string(), i);
      // The source frame has y up and z toward the viewer; flip both.
      face[i] = Eigen::Vector3d(p[0].get<double>(), -p[1].get<double>(), -p[2].get<double>());
    }
  } catch (const nlohmann::json::exception& e) {
    Fail(ExitCode::kAssets, "{}: not a mean face ({})", path.string(), JsonErrorText(e));
  }
  return face;
}

}  // namespace gazedirector
