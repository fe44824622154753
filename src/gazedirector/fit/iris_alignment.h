#pragma once

#include <array>

#include <opencv2/core.hpp>

#include "gazedirector/geometry/camera.h"
#include "gazedirector/model/parameters.h"
#include "gazedirector/render/renderer.h"

namespace gazedirector {

// How far each fitted iris sits from the photo's own, without labels: the
// distance between the fitted iris centre (the limbus ring's centre,
// projected) and the centroid of the darkest 30% of the photo's pixels that
// the fitted eyeball covers, in fitted iris radii (the projected ring's
// largest radius). The iris and pupil are the darkest part of an open eye,
// so a fit on its iris reads about 0.1-0.4 and one that lost it 1 or more;
// lashes and lid shadow inside a tight fit keep it above 0. NaN for an eye
// not in `eyes` or showing fewer than kMinEyeballPixels.
std::array<double, 2> IrisMisalignment(const cv::Mat& image, const Camera& camera, const Parameters& phi,
                                       std::array<bool, 2> eyes, Renderer& renderer);

// The larger of the two, 0 where neither eye shows enough eyeball to tell.
double WorstIrisMisalignment(const cv::Mat& image, const Camera& camera, const Parameters& phi,
                             std::array<bool, 2> eyes, Renderer& renderer);

inline constexpr int kMinEyeballPixels = 12;

}  // namespace gazedirector
