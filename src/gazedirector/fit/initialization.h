#pragma once

#include "gazedirector/face/face.h"
#include "gazedirector/geometry/camera.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/model/parameters.h"

namespace gazedirector {

inline constexpr double kAverageInterocularMm = 63.0;
// The dlib landmarks of each model eye's corners: [eye][0 inner, 1 outer]
// (the model's left eye is the subject's left, on the image right).
inline constexpr int kCornerLandmarks[2][2] = {{42, 45}, {39, 36}};

// The paper's initialisation from facial landmarks: the eye regions take the
// head's rotation, their translation is fitted so that the model's eye
// corners project onto the four landmarked corners (at the average
// interocular distance), and everything else starts at its mean: shape,
// texture, an average iris, gaze straight ahead and a basic light.
Parameters InitializeFromLandmarks(const Face& face, const Camera& camera, const EyeRegionModel& model);

// The model's eye corners (the canthi: inner, outer) of one eye in the camera
// frame for Φ, with the mean shape and resting lids.
std::array<Eigen::Vector3d, 2> ModelEyeCorners(const Parameters& phi, const EyeRegionModel& model, int eye);

// Where an eye corner should appear: eye, corner (0 inner, 1 outer), pixel.
struct CornerTarget {
  int eye;
  int corner;
  Eigen::Vector2d pixel;
};

// The translation that puts the model's eye corners at the targets (least
// squares, Gauss-Newton), starting from Φ's.
Eigen::Vector3d FitTranslationToCorners(const Parameters& phi, const EyeRegionModel& model, const Camera& camera,
                                        const std::vector<CornerTarget>& targets);

}  // namespace gazedirector
