#pragma once

#include <array>
#include <cstddef>

#include <opencv2/core.hpp>

#include "gazedirector/redirect/eye_colour_match.h"
#include "gazedirector/render/renderer.h"

namespace gazedirector {

// The photo's own eye surface carried onto the re-posed eyeballs, the
// rendering where it shows none, and the checks on what it carries.

// Photo pixels whose modelled reflection is brighter than this (luminance) are
// not reused: the model places a highlight only roughly, and what it misses
// would travel with the iris. Fainter reflections are subtracted instead.
inline constexpr float kHighlight = 0.06f;

// The colour (BGR) of the rendering's `i`-th foreground pixel.
inline cv::Vec3f RenderedBgr(const RenderBuffers& buffers, std::size_t i) {
  const Eigen::Index row = static_cast<Eigen::Index>(i);
  return {buffers.colour(row, 2), buffers.colour(row, 1), buffers.colour(row, 0)};
}

// The new eyeballs over the eye region: the rendering everywhere, and the
// photo's own surface where it was found (transfer_mask), with where each
// such pixel came from.
struct EyeballTransfer {
  cv::Mat rendered, transferred;  // CV_32FC3
  cv::Mat transfer_mask;          // 8-bit
  cv::Mat from_depth;             // sclera: how deep in the fitted opening its source was
  cv::Mat moved_by;               // how far its source was, in pixels
  cv::Mat source;                 // where it came from (CV_32FC2), when kept for a recipe
  cv::Mat highlight;              // the old reflections taken off it there (CV_32FC3), likewise
  cv::Mat relit_by;               // and the factor it was relit by (CV_32F), likewise
  EyeColourMatches colours;

  EyeballTransfer(cv::Size size, bool keep_sources)
      : rendered(size, CV_32FC3, cv::Scalar::all(0)),
        transferred(size, CV_32FC3, cv::Scalar::all(0)),
        transfer_mask(size, CV_8UC1, cv::Scalar(0)),
        from_depth(size, CV_32FC1, cv::Scalar(0)),
        moved_by(size, CV_32FC1, cv::Scalar(0)) {
    if (keep_sources) {
      source = cv::Mat(size, CV_32FC2, cv::Scalar::all(0));
      highlight = cv::Mat(size, CV_32FC3, cv::Scalar::all(0));
      relit_by = cv::Mat(size, CV_32F, cv::Scalar(1));
    }
  }
};

// What the transfer of the photo's eye surface onto the new eyeballs reads,
// all over the eye region.
struct TransferInputs {
  const cv::Mat& surface;        // the photo (CV_32FC3), its glints filled in
  const cv::Mat& source;         // per pixel: where the re-posed surface point was in the photo (CV_32FC2)
  const cv::Mat& mirror_source;  // and where its three mirror images were (CV_32FC(6))
  const cv::Mat& cornea;         // the re-posed eyeballs' cornea attribute
  const cv::Mat& source_depth;   // pixels from the lids inside the fitted opening
  const cv::Mat& target_depth;   // and inside the re-posed one
  float margin_px;
  double gain;                   // the chosen environment's reflections on the fitted eyes: gain x old_specular
  const cv::Mat& old_specular;
  std::array<float, 2> slit;     // per eye, how much it is a slit of lashes (0-1)
  const cv::Mat& fitted_luminance;  // the fit's rendering's luminance (CV_32F)
};

// The new eyeballs (`target`): the rendering everywhere, and the photo's own
// eye surface where the fitted eyeball (`fitted`) showed it, or showed its
// mirror image (away from old highlights), when `reuse_photo`. Right up to
// the fitted lid margin: the lashes' shade there is the photo's, which the
// rendering lacks. The colour match is finished; `keep_sources` keeps
// where each pixel came from (for a CompositeRecipe).
EyeballTransfer TransferEyeballs(const RenderBuffers& fitted, const RenderBuffers& target, const TransferInputs& in,
                                 bool reuse_photo, bool keep_sources);

// Bright photo "iris" moved with the iris is sclera that a fitted iris
// beside the photo's covered: the rendering fills it (where the eye barely
// moves it stays as it was). Dark photo sclera belongs right at the new
// lids; dragged deeper into the new opening it would draw streaks across
// the white, which the rendering fills. So is dark "sclera" from deep in the
// fitted opening that moves: the photo's iris where the fit's sat beside it
// or was smaller, which would draw a dark patch beside the new iris. Where
// the eye barely moves it is left alone: such an eye must keep its iris. Returns the
// clear sclera kept, which gives rendered sclera its colour (NearbyColour),
// not the lashes' shade.
cv::Mat DropMisleadingTransfers(EyeballTransfer& transfer, const RenderBuffers& target, const cv::Mat& cornea,
                                const cv::Mat& target_depth, float margin_px);

// The pixel of `carried` (8-bit, non-zero) nearest to `at`, searched out to
// `reach` pixels; `at` itself where none is.
cv::Point NearestCarried(const cv::Mat& carried, const cv::Point& at, int reach);

// Small holes in the photo's iris carried onto the new one (samples at the
// fitted eye's modelled highlight, specks of bright "iris"), enclosed by
// carried iris, take the sample of the nearest carried iris pixel. The
// rendering would fill them with whatever its own iris shows there: a dark
// speck where its pupil lies beside the photo's (d19.jpg).
void FillIrisHoles(EyeballTransfer& transfer, const RenderBuffers& target, const cv::Mat& cornea);

}  // namespace gazedirector
