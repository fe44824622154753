#pragma once

#include <array>

#include <Eigen/Core>

#include "gazedirector/face/face.h"
#include "gazedirector/fit/fitter.h"

namespace gazedirector {

// One face of one image or frame: the face the tracker found and the model
// fitted to it.
struct FaceFit {
  Face face;
  FitResult fit;
  bool warm = false;  // started from the previous frame's fit
  // The landmarks saw the eyes closed (a blink in a video): the gaze was held
  // at the last open frame's, the lids fitted.
  bool eyes_closed = false;
  // Which eyes were fitted: both for a face, one for an eye patch.
  std::array<bool, 2> eyes = {true, true};
  // False for an eye patch, fitted from the crop's framing: `face` is empty.
  bool has_face = true;
};

// One eye's gaze in camera coordinates (millimetres; the gaze is the unit
// optical axis, pointing out of the eye).
struct EyeGaze {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d gaze = Eigen::Vector3d(0, 0, -1);
  double pitch_deg = 0;  // relative to the head, from Φ (up +)
  double yaw_deg = 0;    // relative to the head (toward the subject's left +)
};

// Both eyes' gaze (indexed by Eye) for Φ.
std::array<EyeGaze, 2> EyeGazes(const Parameters& phi);

// OpenFace's gaze angles of a gaze vector in camera coordinates, radians:
// x = atan2(g.x, -g.z) (positive when looking to the image right),
// y = atan2(g.y, -g.z) (positive when looking down).
Eigen::Vector2d GazeAngles(const Eigen::Vector3d& gaze);

}  // namespace gazedirector
