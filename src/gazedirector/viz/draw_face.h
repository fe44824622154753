#pragma once

#include <opencv2/core.hpp>

#include "gazedirector/face/face.h"
#include "gazedirector/geometry/camera.h"

namespace gazedirector {

// Draws a face's box, id and confidence, its landmarks as contours, and its
// head pose as x (red), y (green) and z (blue) axes at the nose.
void DrawFace(cv::Mat& image, const Face& face, const Camera& camera);

// Line thickness and font scale that read well at this image size.
int LineThickness(const cv::Mat& image);

}  // namespace gazedirector
