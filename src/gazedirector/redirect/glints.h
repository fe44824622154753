#pragma once

#include <array>

#include <opencv2/core.hpp>

#include "gazedirector/geometry/camera.h"
#include "gazedirector/model/parameters.h"
#include "gazedirector/render/renderer.h"

namespace gazedirector {

// The photo's corneal glints: reflections of small bright lights, brighter
// than the sclera, on or beside a fitted cornea. A glint does not travel
// with the iris: it lies where the cornea's normal halves the angle between
// the light and the camera, so it moves with the cornea's centre of
// curvature (GlintShifts).
struct Glints {
  cv::Mat light;    // CV_32FC3: what the glints add to the eye beneath them (zero elsewhere)
  cv::Mat surface;  // CV_32FC3: the photo with its glints filled in from the iris around them (empty if none)
  cv::Mat filled;   // 8-bit: where `surface` was filled in, the glints and a pixel around them (empty if none)
  std::array<bool, 2> found = {false, false};
};

// The glints of the photo's eyes (`photo`, CV_32FC3) as fitted: `fitted`
// holds the fit rasterized over the photo, `cornea` its cornea attribute
// (Renderer::CorneaAttribute interpolated over it). A glint is a spot on a
// fitted iris standing out of dark iris around it: brighter than all of its
// sclera (then with the bright patch it lies in, which, over 15% of the iris,
// must lie in dark iris too), or small (at most 3% of the iris) and brighter
// than the sclera's median; with its rim. Patches over a quarter of the iris
// (glasses, a window) are not glints.
Glints FindGlints(const cv::Mat& photo, const RenderBuffers& fitted, const cv::Mat& cornea);

// How far each eye's glints (indexed by Eye) move in `camera`'s image when
// the eyes turn from `fitted` to `target`: as far as the centre of the
// cornea's curvature (topology::kCorneaCentreMm in front of the eyeball's
// centre), about 0.58 of the iris's motion.
std::array<cv::Vec2f, 2> GlintShifts(const Parameters& fitted, const Parameters& target, const Camera& camera);

// `glints` moved by `shifts` onto the eyeballs rendered in `target` (zero elsewhere).
cv::Mat MovedGlints(const Glints& glints, const std::array<cv::Vec2f, 2>& shifts, const RenderBuffers& target);

}  // namespace gazedirector
