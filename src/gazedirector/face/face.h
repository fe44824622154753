#pragma once

#include <array>

#include <Eigen/Core>
#include <opencv2/core/types.hpp>

namespace gazedirector {

inline constexpr int kNumLandmarks = 68;
// The 68 iBUG points in image pixels, in dlib's order (36-41: the subject's
// right eye, on the image left; 42-47: the left eye).
using Landmarks68 = std::array<Eigen::Vector2d, kNumLandmarks>;

inline Landmarks68 ZeroLandmarks() {
  Landmarks68 landmarks;
  landmarks.fill(Eigen::Vector2d::Zero());  // Eigen leaves value-initialised vectors undefined
  return landmarks;
}

// The head frame: origin at the mean face's origin (inside the head), x toward
// the subject's left (image right for a frontal face), y down, z into the head,
// millimetres. `rotation` and `translation` map head points to the camera:
// p_cam = rotation * p_head + translation. A frontal face has rotation = I.
struct HeadPose {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double reprojection_error_px = 0;  // RMS over the landmarks used
};

struct Face {
  int id = 0;
  cv::Rect2d box;           // the face box the landmark predictor was given
  double box_roll = 0;      // ... turned by this about its centre (radians, see turned_crop.h)
  double confidence = 0;    // in [0, 1]; >= 0.5 when the detector sees a face there
  Landmarks68 landmarks = ZeroLandmarks();
  HeadPose pose;

  double InterocularDistance() const { return (landmarks[45] - landmarks[36]).norm(); }
};

}  // namespace gazedirector
