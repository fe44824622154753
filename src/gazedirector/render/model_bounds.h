#pragma once

#include <array>

#include <opencv2/core.hpp>

#include "gazedirector/geometry/camera.h"
#include "gazedirector/model/eye_region_model.h"

namespace gazedirector {

// The image rectangle the facial eye regions of `eyes` project to, grown by
// `margin` of its size on each side and clipped to the image (empty when the
// model is outside it or behind the camera).
cv::Rect ModelBounds(const PosedModel& posed, const Camera& camera, double margin = 0.04,
                     std::array<bool, 2> eyes = {true, true});

// The image rectangle both eyeballs of `posed` project to, a pixel wider on
// each side and clipped to the image (empty when they are outside it or
// behind the camera): every pixel they can cover.
cv::Rect EyeballBounds(const PosedModel& posed, const Camera& camera);

}  // namespace gazedirector
