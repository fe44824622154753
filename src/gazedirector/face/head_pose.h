#pragma once

#include "gazedirector/face/face.h"
#include "gazedirector/face/mean_face.h"
#include "gazedirector/geometry/camera.h"

namespace gazedirector {

// How the mean face is aligned to a face's 2D landmarks.
enum class HeadPoseMethod {
  // Perspective-n-point: the pose whose projection of the mean face best
  // matches the landmarks, in pixels (the default).
  kPerspectiveNPoint,
  // The paper's: Kabsch alignments of the mean face to 3D landmarks. The
  // paper's tracker gave 3D landmarks and dlib's are 2D, so each landmark is
  // lifted onto its line of sight where the posed mean face comes closest,
  // and the two steps alternate (Lu, Hager and Mjolsness's orthogonal
  // iteration): the distance in space falls at every step.
  kKabsch,
};

// Head pose from 2D landmarks and the mean 3D face, aligned on the rigid
// landmarks (brows, nose and eyes). With `previous` the solver starts from
// the last frame's pose, which keeps video pose steady.
HeadPose EstimateHeadPose(const Landmarks68& landmarks, const MeanFace& mean_face, const Camera& camera,
                          const HeadPose* previous = nullptr,
                          HeadPoseMethod method = HeadPoseMethod::kPerspectiveNPoint);

}  // namespace gazedirector
