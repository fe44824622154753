#include "gazedirector/redirect/gaze_target.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "gazedirector/geometry/rotation.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/model/eyelid_rig.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace {

// How far re-posed eyes may converge, degrees.
constexpr double kMaxVergence = 30;

// From the model's gaze convention: d = (sin y cos p, -sin p, -cos y cos p).
Eigen::Vector3d DirectionOf(double pitch_deg, double yaw_deg) { return EyeRegionModel::GazeInHead(pitch_deg, yaw_deg); }

// Beyond a quarter turn a direction points behind the head and an offset wraps around: a typo, not a target.
void CheckAngles(const char* what, double pitch_deg, double yaw_deg) {
  if (!WithinQuarterTurn(pitch_deg) || !WithinQuarterTurn(yaw_deg)) {
    Fail(ExitCode::kUsage, "{} pitch {}, yaw {}: each must be a number of degrees within -90 to 90", what, pitch_deg,
         yaw_deg);
  }
}

}  // namespace

GazeTarget GazeTarget::Point(const Eigen::Vector3d& point) {
  GazeTarget target;
  if (!point.allFinite() || point.z() == 0) {
    Fail(ExitCode::kUsage, "look-at point ({}, {}, {}): needs three finite millimetres, z not 0", point.x(), point.y(),
         point.z());
  }
  target.kind = Kind::kPoint;
  target.point = point;
  return target;
}

GazeTarget GazeTarget::Direction(double pitch_deg, double yaw_deg, Frame frame) {
  GazeTarget target;
  CheckAngles("gaze direction", pitch_deg, yaw_deg);
  target.kind = Kind::kDirection;
  target.pitch_deg = pitch_deg, target.yaw_deg = yaw_deg, target.frame = frame;
  return target;
}

GazeTarget GazeTarget::Offset(double pitch_deg, double yaw_deg) {
  GazeTarget target;
  CheckAngles("gaze offset", pitch_deg, yaw_deg);
  target.kind = Kind::kOffset;
  target.pitch_deg = pitch_deg, target.yaw_deg = yaw_deg;
  return target;
}

std::string GazeTarget::Describe() const {
  switch (kind) {
    case Kind::kCamera: return "the camera";
    case Kind::kPoint: return fmt::format("the point ({:.0f}, {:.0f}, {:.0f}) mm", point.x(), point.y(), point.z());
    case Kind::kDirection:
      return fmt::format("pitch {:.1f} yaw {:.1f} deg ({} frame)", pitch_deg, yaw_deg, frame == Frame::kHead ? "head" : "camera");
    case Kind::kOffset: return fmt::format("the fitted gaze moved by pitch {:+.1f} yaw {:+.1f} deg", pitch_deg, yaw_deg);
  }
  return "";
}

nlohmann::json GazeTarget::ToJson() const {
  switch (kind) {
    case Kind::kCamera: return {{"camera", true}};
    case Kind::kPoint: return {{"look_at", {point.x(), point.y(), point.z()}}};
    case Kind::kDirection: return {{"gaze", {pitch_deg, yaw_deg}}, {"frame", frame == Frame::kHead ? "head" : "camera"}};
    case Kind::kOffset: return {{"offset", {pitch_deg, yaw_deg}}};
  }
  return {};
}

GazeTarget GazeTarget::FromJson(const nlohmann::json& json) {
  auto numbers = [&](const char* key, std::size_t count) {
    const nlohmann::json& value = json.at(key);
    if (!value.is_array() || value.size() != count) {
      Fail(ExitCode::kBadInput, "gaze target \"{}\" needs {} numbers", key, count);
    }
    std::vector<double> out;
    for (const auto& v : value) {
      if (!v.is_number()) Fail(ExitCode::kBadInput, "gaze target \"{}\" holds a non-number", key);
      out.push_back(v.get<double>());
    }
    return out;
  };
  if (json.is_string() && json.get<std::string>() == "camera") return Camera();
  if (!json.is_object()) Fail(ExitCode::kBadInput, "a gaze target must be \"camera\" or an object");
  if (json.contains("camera")) return Camera();
  if (json.contains("look_at")) {
    const auto p = numbers("look_at", 3);
    if (!(p[2] > 0) && !(p[2] < 0)) Fail(ExitCode::kBadInput, "look_at: the point's z must not be 0");
    return Point({p[0], p[1], p[2]});
  }
  if (json.contains("gaze")) {
    const auto g = numbers("gaze", 2);
    const std::string frame = json.value("frame", std::string("camera"));
    if (frame != "camera" && frame != "head") Fail(ExitCode::kBadInput, "gaze frame must be \"camera\" or \"head\", not \"{}\"", frame);
    return Direction(g[0], g[1], frame == "head" ? Frame::kHead : Frame::kCamera);
  }
  if (json.contains("offset")) {
    const auto o = numbers("offset", 2);
    return Offset(o[0], o[1]);
  }
  Fail(ExitCode::kBadInput, "a gaze target needs one of camera, look_at, gaze, offset");
}

double EyelidFollow::LidPitch(double lid_pitch_deg, double pitch_change_deg) const {
  if (pitch_change_deg <= 0) return lid_pitch_deg + down * pitch_change_deg;
  const double within = keep_pace_beyond ? std::min(pitch_change_deg, up_measured_deg) : pitch_change_deg;
  const double lid = lid_pitch_deg + up * within;
  const double beyond = pitch_change_deg - within;
  if (beyond <= 0) return lid;
  const EyelidRigSettings rig;
  return rig.LidPitchForUpperLidTurn(rig.UpperLidTurn(lid) + beyond);
}

Parameters Retarget(const Parameters& phi, const GazeTarget& target, EyelidFollow follow) {
  Parameters out = phi;
  const Eigen::Matrix3d rotation = phi.rotation();
  switch (target.kind) {
    case GazeTarget::Kind::kCamera:
    case GazeTarget::Kind::kPoint: {
      const Eigen::Vector3d point = target.kind == GazeTarget::Kind::kCamera ? Eigen::Vector3d::Zero() : target.point;
      const Eigen::Vector3d angles = EyeRegionModel::FixationAngles(phi, point);
      out.gaze_pitch() = angles.x();
      out.gaze_yaw() = angles.y();
      out.vergence() = angles.z();
      break;
    }
    case GazeTarget::Kind::kDirection: {
      Eigen::Vector3d direction = DirectionOf(target.pitch_deg, target.yaw_deg);
      if (target.frame == GazeTarget::Frame::kCamera) direction = rotation.transpose() * direction;
      const Eigen::Vector2d pitch_yaw = EyeRegionModel::PitchYawInHead(direction);
      out.gaze_pitch() = pitch_yaw.x();
      out.gaze_yaw() = pitch_yaw.y();
      break;
    }
    case GazeTarget::Kind::kOffset:
      out.gaze_pitch() += target.pitch_deg;
      out.gaze_yaw() += target.yaw_deg;
      break;
  }
  out.gaze_pitch() = std::clamp(out.gaze_pitch(), -kMaxRedirectPitchDeg, kMaxRedirectPitchDeg);
  out.gaze_yaw() = std::clamp(out.gaze_yaw(), -kMaxRedirectYawDeg, kMaxRedirectYawDeg);
  out.vergence() = std::clamp(out.vergence(), -2.0, kMaxVergence);
  const double change = out.gaze_pitch() - phi.gaze_pitch();
  out.eyelid_pitch() = follow.LidPitch(phi.eyelid_pitch(), change);
  return out;
}

bool AtTheEyesReach(const Parameters& retargeted) {
  return std::abs(retargeted.gaze_pitch()) >= kMaxRedirectPitchDeg || std::abs(retargeted.gaze_yaw()) >= kMaxRedirectYawDeg;
}

std::string ReachDescription() {
  return fmt::format("the eyes turn at most {:g} deg aside and {:g} deg up or down", kMaxRedirectYawDeg,
                     kMaxRedirectPitchDeg);
}

Parameters BlendGaze(const Parameters& a, const Parameters& b, double t) {
  Parameters out = a;
  for (Block block : {Block::kGaze, Block::kEyelid}) {
    const BlockLayout& layout = LayoutOf(block);
    for (int i = layout.offset; i < layout.offset + layout.size; ++i) out[i] = (1 - t) * a[i] + t * b[i];
  }
  return out;
}

}  // namespace gazedirector
