#pragma once

#include "gazedirector/face/face.h"
#include "gazedirector/face/mean_face.h"
#include "gazedirector/geometry/camera.h"

namespace gazedirector {

// Head pose from 2D landmarks and the mean 3D face (perspective-n-point on
// the rigid landmarks: brows, nose and eyes). With `previous` the solver
// starts from the last frame's pose, which keeps video pose steady.
HeadPose EstimateHeadPose(const Landmarks68& landmarks, const MeanFace& mean_face, const Camera& camera,
                          const HeadPose* previous = nullptr);

}  // namespace gazedirector
