#include "gazedirector/fit/face_fit.h"

#include <cmath>

#include "gazedirector/model/eye_region_model.h"

namespace gazedirector {

std::array<EyeGaze, 2> EyeGazes(const Parameters& phi) {
  const Eigen::Matrix3d rotation = phi.rotation();
  std::array<EyeGaze, 2> eyes;
  for (int eye = 0; eye < 2; ++eye) {
    EyeGaze& out = eyes[eye];
    out.pitch_deg = phi.gaze_pitch();
    out.yaw_deg = EyeRegionModel::EyeYaw(phi, eye);
    out.centre = rotation * EyeRegionModel::EyeCentreInHead(phi, eye) + phi.translation();
    out.gaze = (rotation * EyeRegionModel::GazeInHead(out.pitch_deg, out.yaw_deg)).normalized();
  }
  return eyes;
}

Eigen::Vector2d GazeAngles(const Eigen::Vector3d& gaze) {
  return {std::atan2(gaze.x(), -gaze.z()), std::atan2(gaze.y(), -gaze.z())};
}

}  // namespace gazedirector
