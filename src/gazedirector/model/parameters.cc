#include "gazedirector/model/parameters.h"

#include <cmath>

#include <fmt/format.h>

#include "gazedirector/geometry/rotation.h"
#include "gazedirector/model/eye_region_topology.h"
#include "gazedirector/util/error.h"

namespace gazedirector {

ParameterMask MaskOf(std::initializer_list<Block> blocks) {
  ParameterMask mask{};
  for (Block block : blocks) {
    const BlockLayout& layout = LayoutOf(block);
    for (int i = 0; i < layout.size; ++i) mask[layout.offset + i] = true;
  }
  return mask;
}

void Hold(ParameterMask& free, std::initializer_list<Block> blocks) {
  const ParameterMask held = MaskOf(blocks);
  for (int i = 0; i < kNumParameters; ++i) free[i] = free[i] && !held[i];
}

ParameterMask AllParameters() {
  ParameterMask mask;
  mask.fill(true);
  return mask;
}

Parameters::Parameters() {
  values.setZero();
  iris_size() = 0.95;
  pupil_size() = topology::kTexturePupilSize;
  block<Block::kIrisColour>() = Eigen::Vector3d(0.45, 0.32, 0.22);
  block<Block::kScleraTint>() = Eigen::Vector3d(0.85, 0.80, 0.78);
  interocular() = 63.0;
  block<Block::kTranslation>() = Eigen::Vector3d(0, 0, 500);
  block<Block::kAmbient>() = Eigen::Vector3d(0.6, 0.6, 0.6);
  block<Block::kLightColour>() = Eigen::Vector3d(0.4, 0.4, 0.4);
  block<Block::kLightDirection>() = Eigen::Vector2d(20, 0);
}

void Parameters::set_rotation(const Eigen::Matrix3d& rotation) {
  const Eigen::Vector3d euler = EulerXYZFromRotation(rotation);
  block<Block::kRotation>() = Eigen::Vector3d(RadToDeg(euler.x()), RadToDeg(euler.y()), RadToDeg(euler.z()));
}

Eigen::Matrix3d Parameters::rotation() const {
  const Eigen::Vector3d deg = rotation_deg();
  return RotationFromEulerXYZ(Eigen::Vector3d(DegToRad(deg.x()), DegToRad(deg.y()), DegToRad(deg.z())));
}

Eigen::Vector3d Parameters::LightDirection() const {
  const double pitch = DegToRad(light_direction_deg().x());
  const double yaw = DegToRad(light_direction_deg().y());
  // Toward the camera (-z) at zero; up is -y in the camera frame.
  return Eigen::Vector3d(std::cos(pitch) * std::sin(yaw), -std::sin(pitch), -std::cos(pitch) * std::cos(yaw));
}

Eigen::Matrix<double, 3, 2> Parameters::LightDirectionJacobian() const {
  const double pitch = DegToRad(light_direction_deg().x());
  const double yaw = DegToRad(light_direction_deg().y());
  const double sp = std::sin(pitch), cp = std::cos(pitch), sy = std::sin(yaw), cy = std::cos(yaw);
  Eigen::Matrix<double, 3, 2> jacobian;
  jacobian.col(0) = Eigen::Vector3d(-sp * sy, -cp, sp * cy);
  jacobian.col(1) = Eigen::Vector3d(cp * cy, 0.0, cp * sy);
  return DegToRad(1.0) * jacobian;
}

nlohmann::json Parameters::ToJson() const {
  nlohmann::json json = nlohmann::json::object();
  for (const BlockLayout& layout : kBlockLayout) {
    if (layout.size == 1) {
      json[std::string(layout.name)] = values[layout.offset];
    } else {
      nlohmann::json array = nlohmann::json::array();
      for (int i = 0; i < layout.size; ++i) array.push_back(values[layout.offset + i]);
      json[std::string(layout.name)] = array;
    }
  }
  return json;
}

Parameters Parameters::FromJson(const nlohmann::json& json) {
  if (!json.is_object()) Fail(ExitCode::kBadInput, "model parameters must be a JSON object");
  Parameters parameters;
  for (const BlockLayout& layout : kBlockLayout) {
    const auto entry = json.find(std::string(layout.name));
    if (entry == json.end()) continue;
    if (layout.size == 1 && entry->is_number()) {
      parameters.values[layout.offset] = entry->get<double>();
      continue;
    }
    if (!entry->is_array() || static_cast<int>(entry->size()) != layout.size) {
      Fail(ExitCode::kBadInput, "model parameter \"{}\" needs {} number{}", layout.name, layout.size, layout.size > 1 ? "s" : "");
    }
    for (int i = 0; i < layout.size; ++i) {
      if (!(*entry)[i].is_number()) Fail(ExitCode::kBadInput, "model parameter \"{}\" holds a non-number", layout.name);
      parameters.values[layout.offset + i] = (*entry)[i].get<double>();
    }
  }
  for (const auto& [key, value] : json.items()) {
    bool known = false;
    for (const BlockLayout& layout : kBlockLayout) known = known || key == layout.name;
    if (!known) Fail(ExitCode::kBadInput, "unknown model parameter \"{}\"", key);
  }
  if (!(parameters.interocular() > 0) || !(parameters.iris_size() > 0)) {
    Fail(ExitCode::kBadInput, "interocular distance and iris size must be positive");
  }
  if (!(parameters.pupil_size() > 0 && parameters.pupil_size() < 1)) {
    Fail(ExitCode::kBadInput, "pupil_size: the pupil's radius relative to the iris's must be between 0 and 1");
  }
  if (!(parameters.translation().z() > 0)) {
    Fail(ExitCode::kBadInput, "translation_mm: the eyes must be in front of the camera (z > 0)");
  }
  // Past a quarter turn the angles wrap around: an edit gone wrong, not a pose.
  if (!WithinQuarterTurn(parameters.gaze_pitch()) || !WithinQuarterTurn(parameters.gaze_yaw()) ||
      !WithinQuarterTurn(parameters.eyelid_pitch())) {
    Fail(ExitCode::kBadInput, "gaze_pitch_yaw_vergence_deg and eyelid_pitch_deg: angles must be within -90 to 90 degrees");
  }
  return parameters;
}

Block Parameters::BlockOf(int index) {
  for (const BlockLayout& layout : kBlockLayout) {
    if (index >= layout.offset && index < layout.offset + layout.size) return layout.block;
  }
  Fail(ExitCode::kInternal, "parameter index {} out of range", index);
}

std::string Parameters::NameOf(int index) {
  const BlockLayout& layout = LayoutOf(BlockOf(index));
  if (layout.size == 1) return std::string(layout.name);
  return fmt::format("{}[{}]", layout.name, index - layout.offset);
}

}  // namespace gazedirector
