#pragma once

#include <functional>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "gazedirector/eval/columbia.h"
#include "gazedirector/fit/fitter.h"
#include "gazedirector/redirect/gaze_target.h"

namespace gazedirector {

// One redirected Columbia crop: the subject's 0V 0H crop (head pose 0)
// redirected to another (V, H), compared with the real crop of that gaze.
struct RedirectColumbiaCase {
  ColumbiaCrop source;
  ColumbiaCrop target;
  // Mean absolute per-pixel error (8-bit levels, over pixels and channels):
  double error_none = 0;      // the source crop itself
  double error_eyeballs = 0;  // eyeballs redirected, eyelids as they were
  double error_full = 0;      // eyeballs and eyelids redirected
  bool fit_good = false;
  // Where the real crop's skin lies relative to the source crop's (pixels),
  // applied to all three conditions before comparing (zero unregistered).
  cv::Point2f shift;
};

struct RedirectColumbiaOptions {
  EyelidFollow eyelid_follow;  // how far the eyelids follow each change of pitch (see Retarget)
  // Redirect by this fraction of each label's change of gaze. 1 is the
  // evaluation; other values show how the pixel error weighs a shortfall
  // against an overshoot.
  double angle_scale = 1.0;
  // Register each real crop to its source crop on the skin around the eye
  // before comparing (see RegisterOnSkin).
  bool register_crops = true;
};

// Runs the paper's redirection evaluation on the crops at head pose 0.
// `on_output` receives each fully redirected crop (condition c); `progress`
// the number done.
std::vector<RedirectColumbiaCase> EvaluateRedirectColumbia(
    const std::vector<ColumbiaCrop>& crops, std::shared_ptr<const EyeRegionModel> model, const FitOptions& fit_options,
    const RedirectColumbiaOptions& options,
    const std::function<void(const RedirectColumbiaCase&, const cv::Mat&)>& on_output = nullptr,
    const std::function<void(int done, int total)>& progress = nullptr);

// The translation that carries `source` onto `real` (real(x + shift) ~
// source(x)), estimated on the skin outside `eye` (the eye opening and lids,
// which move with gaze). Columbia's crops are centred on each photo's own eye
// landmarks, which follow the lids: looking 10 degrees down shifts the crop by
// about 2.4 px. Zero where the estimate fails.
cv::Point2f RegisterOnSkin(const cv::Mat& source, const cv::Mat& real, const cv::Rect& eye);

// `image` moved by `shift` (pixels), its borders replicated.
cv::Mat Shifted(const cv::Mat& image, cv::Point2f shift);

// Mean absolute difference of two 8-bit images of the same size.
double MeanAbsoluteError(const cv::Mat& a, const cv::Mat& b);

}  // namespace gazedirector
