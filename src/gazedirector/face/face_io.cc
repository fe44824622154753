#include "gazedirector/face/face_io.h"

#include <fmt/format.h>

#include "gazedirector/geometry/rotation.h"
#include "gazedirector/io/json_format.h"

namespace gazedirector {
nlohmann::json ToJson(const HeadPose& pose) {
  const Eigen::Vector3d euler = EulerXYZFromRotation(pose.rotation);
  nlohmann::json rotation = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) {
    rotation.push_back({RoundTo(pose.rotation(r, 0), 6), RoundTo(pose.rotation(r, 1), 6), RoundTo(pose.rotation(r, 2), 6)});
  }
  return {{"translation_mm", {RoundTo(pose.translation.x(), 3), RoundTo(pose.translation.y(), 3), RoundTo(pose.translation.z(), 3)}},
          {"rotation_xyz_rad", {RoundTo(euler.x(), 5), RoundTo(euler.y(), 5), RoundTo(euler.z(), 5)}},
          {"rotation_matrix", rotation},
          {"reprojection_error_px", RoundTo(pose.reprojection_error_px, 3)}};
}

nlohmann::json ToJson(const Face& face) {
  nlohmann::json landmarks = nlohmann::json::array();
  for (const auto& p : face.landmarks) landmarks.push_back({RoundTo(p.x(), 3), RoundTo(p.y(), 3)});
  return {{"face_id", face.id},
          {"confidence", RoundTo(face.confidence, 4)},
          {"box", {RoundTo(face.box.x, 2), RoundTo(face.box.y, 2), RoundTo(face.box.width, 2), RoundTo(face.box.height, 2)}},
          {"box_roll_deg", RoundTo(RadToDeg(face.box_roll), 2)},
          {"landmarks", landmarks},
          {"head_pose", ToJson(face.pose)}};
}

nlohmann::json ToJson(const Camera& camera) {
  return {{"fx", camera.fx}, {"fy", camera.fy}, {"cx", camera.cx}, {"cy", camera.cy},
          {"width", camera.width}, {"height", camera.height}};
}

Camera CameraFromJson(const nlohmann::json& json) {
  return {json.at("fx").get<double>(), json.at("fy").get<double>(), json.at("cx").get<double>(),
          json.at("cy").get<double>(), json.at("width").get<int>(), json.at("height").get<int>()};
}

std::vector<std::string> FaceCsvColumns() {
  std::vector<std::string> columns = {"frame",   "face_id", "timestamp", "confidence", "success", "pose_Tx",
                                      "pose_Ty", "pose_Tz", "pose_Rx",   "pose_Ry",    "pose_Rz"};
  for (int i = 0; i < kNumLandmarks; ++i) columns.push_back(fmt::format("x_{}", i));
  for (int i = 0; i < kNumLandmarks; ++i) columns.push_back(fmt::format("y_{}", i));
  return columns;
}

std::vector<std::string> FaceCsvRow(long frame, double timestamp_s, const Face* face) {
  std::vector<std::string> row = {std::to_string(frame), face ? std::to_string(face->id) : "-1",
                                  fmt::format("{:.3f}", timestamp_s), fmt::format("{:.3f}", face ? face->confidence : 0.0),
                                  face ? "1" : "0"};
  if (face == nullptr) {
    row.resize(FaceCsvColumns().size(), "0");
    return row;
  }
  const Eigen::Vector3d euler = EulerXYZFromRotation(face->pose.rotation);
  for (int i = 0; i < 3; ++i) row.push_back(fmt::format("{:.1f}", face->pose.translation[i]));
  for (int i = 0; i < 3; ++i) row.push_back(fmt::format("{:.4f}", euler[i]));
  for (int i = 0; i < kNumLandmarks; ++i) row.push_back(fmt::format("{:.2f}", face->landmarks[i].x()));
  for (int i = 0; i < kNumLandmarks; ++i) row.push_back(fmt::format("{:.2f}", face->landmarks[i].y()));
  return row;
}

}  // namespace gazedirector
