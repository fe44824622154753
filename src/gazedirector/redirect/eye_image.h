#pragma once

#include <opencv2/core.hpp>

namespace gazedirector {

// Small image operations of the redirection, on CV_32FC3 BGR images in [0, 1].

// Rec. 601 luma of a BGR colour.
inline float Luminance(const cv::Vec3f& bgr) { return 0.114f * bgr[0] + 0.587f * bgr[1] + 0.299f * bgr[2]; }

// `image` sampled bilinearly at (x, y), clamped to its edges.
cv::Vec3f Bilinear(const cv::Mat& image, float x, float y);

// An eyeball pixel shows sclera where its cornea flag, interpolated across
// the limbus (Renderer::CorneaAttribute), is under this; else the iris. (The
// rendering's colours switch at the texture's iris edge instead, about half
// a millimetre further in, antialiased: see MixedAcrossEdge.)
inline constexpr float kLimbus = 0.5f;
inline bool IsSclera(const cv::Mat& cornea, int x, int y) { return cornea.at<float>(y, x) < kLimbus; }

// `rect` grown by `margin` pixels on every side, within an image of `size`.
inline cv::Rect GrownWithin(const cv::Rect& rect, int margin, cv::Size size) {
  return (rect + cv::Size(2 * margin, 2 * margin) - cv::Point(margin, margin)) & cv::Rect(cv::Point(), size);
}

// `image` blurred by a Gaussian of `sigma`, computed only where it is needed
// to be right within `area` (zero elsewhere).
cv::Mat BlurredWithin(const cv::Mat& image, const cv::Rect& area, double sigma);

// Softens the seam along the edge of `mask` (8-bit) in `image`: within about
// two `sigma` of it, `image` blurred by a Gaussian of `sigma` is blended in,
// fully on the edge. `area` holds the mask.
void BlurSeam(cv::Mat& image, const cv::Mat& mask, const cv::Rect& area, double sigma);

// Antialiases a hard edge in `image` within `mask` (8-bit): each pixel whose
// centre lies within half a pixel of the edge (`edge_distance`, CV_32F, the
// signed distance in pixels, its sign telling the sides) is mixed with its
// 4-neighbours across it by how much of the pixel lies on each side.
cv::Mat MixedAcrossEdge(const cv::Mat& image, const cv::Mat& mask, const cv::Mat& edge_distance);

// The colour of `image`'s pixels in `shown` (8-bit mask) near each pixel of
// `area`: they are blurred by `sigma` pixels and normalised by how many are
// near, drawn toward `typical` where few are (and `typical` outside `area`).
cv::Mat NearbyColour(const cv::Mat& image, const cv::Mat& shown, const cv::Rect& area, double sigma,
                     const cv::Vec3f& typical);
// The same with a typical colour per pixel (CV_32FC3, the size of `image`).
cv::Mat NearbyColour(const cv::Mat& image, const cv::Mat& shown, const cv::Rect& area, double sigma,
                     const cv::Mat& typical);

// Each pixel's Euclidean distance in pixels to the nearest pixel outside
// `mask` (8-bit; CV_32F, 0 outside): cv::distanceTransform's precise one,
// computed only around the mask, which is all of it.
cv::Mat DepthInside(const cv::Mat& mask);

// The median of `values` (CV_32FC1) under `mask` (8-bit), `none` where the mask is empty.
double MedianUnder(const cv::Mat& values, const cv::Mat& mask, double none);

// The median colour of `image` under `mask` (black where none).
cv::Vec3f MedianColour(const cv::Mat& image, const cv::Mat& mask);

}  // namespace gazedirector
