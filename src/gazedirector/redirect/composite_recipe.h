#pragma once

#include <opencv2/core.hpp>

namespace gazedirector {

// How each pixel of a redirected eye region is made, kept at the size the
// redirector worked at, so that it can be followed over a larger photo of
// the same region: where the eye is decided at the working size (its masks
// and thresholds were tuned there), but every photo sample is taken from the
// photo's own pixels, so its lashes and irises stay sharp. All images are of
// the region's size.
struct CompositeRecipe {
  cv::Rect region;        // the region within the working-size image
  cv::Mat skin_source;    // CV_32FC2: where each pixel fetches the photo (itself, except warped skin)
  cv::Mat eyeball_mask;   // 8-bit: the new eyeballs
  cv::Mat photo_source;   // CV_32FC2: where an eyeball pixel's photo share comes from
  cv::Mat photo_share;    // CV_32F: that share of its colour
  cv::Mat highlight;      // CV_32FC3: taken off the photo's share (the old reflections there)
  cv::Mat photo_gain;     // CV_32F: then multiplying it (relit sclera); empty: 1
  cv::Mat rest;           // CV_32FC3: its colour besides the photo's share (rendering, reflections)
  cv::Mat seam_alpha;     // CV_32F: the eyeball's weight over the warped photo
  cv::Mat glints;         // CV_32FC3: the moved glints, added after the seam is softened (may be empty)
  cv::Mat surface;        // CV_32FC3: the photo with its glints filled in, where glint_fill > 0
  cv::Mat glint_fill;     // CV_32F: 1 where `surface` replaces the photo
};

// `photo` (CV_32FC3) redirected as `recipe` says, where `photo` is the
// working-size image at `scale_x` x `scale_y` its size (pixel centres map
// as cv::resize maps them). Pixels outside the recipe's region are kept.
// `eyeball_mask` (8-bit, of the photo's size) says where the new eyeballs
// are, rasterized at full size; empty: where the recipe's mask, enlarged,
// says (its edge then steps by the scale). Their seam is softened by a
// Gaussian of `seam` pixels (BlurSeam; 0: not at all).
cv::Mat FollowRecipe(const CompositeRecipe& recipe, const cv::Mat& photo, double scale_x, double scale_y,
                     const cv::Mat& eyeball_mask = cv::Mat(), double seam = 0);

}  // namespace gazedirector
