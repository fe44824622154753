#pragma once

#include <opencv2/core.hpp>

#include "gazedirector/fit/face_fit.h"
#include "gazedirector/geometry/camera.h"
#include "gazedirector/render/renderer.h"

namespace gazedirector {

// Draws a fitted model as in the paper's figures: the rendered model blended
// over the photo (`opacity`), the outline of the eye openings, and each
// fitted eye's gaze ray from its eyeball centre. Green when the fit is good,
// orange when not.
void DrawFit(cv::Mat& image, const Camera& camera, const Parameters& phi, bool good, std::array<bool, 2> eyes,
             Renderer& renderer, double opacity = 0.6);

}  // namespace gazedirector
