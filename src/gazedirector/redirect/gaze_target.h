#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "gazedirector/model/parameters.h"

namespace gazedirector {

// Where redirected eyes should look.
struct GazeTarget {
  enum class Kind {
    kPoint,      // a 3D point in camera coordinates (mm); both eyes verge on it
    kCamera,     // eye contact: the camera's centre
    kDirection,  // a direction, pitch and yaw in degrees (in `frame`)
    kOffset,     // a change of the fitted gaze, pitch and yaw in degrees
  };
  enum class Frame { kCamera, kHead };

  Kind kind = Kind::kCamera;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double pitch_deg = 0;  // up +
  double yaw_deg = 0;    // kDirection in the camera frame: toward the image right +; in the head frame: toward the subject's left +
  Frame frame = Frame::kCamera;

  static GazeTarget Camera() { return {}; }
  static GazeTarget Point(const Eigen::Vector3d& point);
  static GazeTarget Direction(double pitch_deg, double yaw_deg, Frame frame);
  static GazeTarget Offset(double pitch_deg, double yaw_deg);

  std::string Describe() const;
  nlohmann::json ToJson() const;
  // {"camera": true} | {"look_at": [x, y, z]} | {"gaze": [pitch, yaw], "frame": "camera"|"head"} | {"offset": [dp, dy]}
  static GazeTarget FromJson(const nlohmann::json& json);
};

// How far the eyelids follow a change of gaze pitch when re-posing, as a
// fraction of it: fully when the eyes look down (the upper lid rides on the
// cornea), less when they look up. Measured on the Columbia crops
// (eval redirect-columbia, crops registered on the skin around the eye):
// following 1.0 down and 0.4 up gives (c) 11.38 against 11.59 for 0.3 both
// ways, better on odd and even subjects alike; 1.25 down or 0 or 1 up do worse.
// Columbia's changes reach 10 deg up; beyond that the upper lid keeps pace
// with the iris, as real upper lids follow vertical gaze about one to one,
// so that a large turn up does not slide the iris under the lid.
struct EyelidFollow {
  double down = 1.0;
  double up = 0.4;
  double up_measured_deg = 10;  // `up` holds for this much of an upward change
  bool keep_pace_beyond = true;

  // The lid pitch after a change of gaze pitch (degrees, up positive).
  double LidPitch(double lid_pitch_deg, double pitch_change_deg) const;
};

// How far re-posed eyes may turn from looking ahead in the head, degrees
// (the model's lids stop looking natural beyond it).
inline constexpr double kMaxRedirectPitchDeg = 30;
inline constexpr double kMaxRedirectYawDeg = 50;

// Φ re-posed to look at `target`: gaze pitch, yaw and (for points) vergence,
// with the eyelids following the change of pitch as `follow` says, within the
// eye's range: a target beyond it (far aside, behind the head) is looked
// toward as far as the eyes turn.
Parameters Retarget(const Parameters& phi, const GazeTarget& target, EyelidFollow follow = {});
// Whether a Φ from Retarget had its gaze stopped at the eyes' range.
bool AtTheEyesReach(const Parameters& retargeted);
// "the eyes turn at most 50 deg aside and 30 deg up or down", for messages.
std::string ReachDescription();

// Blends two gaze poses (gaze and eyelids only; the rest from `a`) by `t` in [0, 1].
Parameters BlendGaze(const Parameters& a, const Parameters& b, double t);

}  // namespace gazedirector
