#pragma once

#include <opencv2/core.hpp>

#include "gazedirector/fit/face_fit.h"
#include "gazedirector/geometry/camera.h"
#include "gazedirector/render/renderer.h"

namespace gazedirector {

// Draws a fitted model as in the paper's figures: the rendered model blended
// over the photo (`opacity`), the outlines of the model (green when the fit
// is good, orange when not), of the eye openings (yellow) and of the irises
// as far as they show (light blue), and each fitted eye's gaze ray from its
// cornea (red).
void DrawFit(cv::Mat& image, const Camera& camera, const Parameters& phi, bool good, std::array<bool, 2> eyes,
             Renderer& renderer, double opacity = 0.6);

}  // namespace gazedirector
