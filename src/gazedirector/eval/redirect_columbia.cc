#include "gazedirector/eval/redirect_columbia.h"

#include <map>
#include <tuple>

#include "gazedirector/io/image_io.h"
#include "gazedirector/redirect/gaze_target.h"
#include "gazedirector/redirect/redirector.h"
#include "gazedirector/util/interrupt.h"

namespace gazedirector {

double MeanAbsoluteError(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat difference;
  cv::absdiff(a, b, difference);
  const cv::Scalar sum = cv::sum(difference);
  return (sum[0] + sum[1] + sum[2]) / (static_cast<double>(a.total()) * a.channels());
}

std::vector<RedirectColumbiaCase> EvaluateRedirectColumbia(
    const std::vector<ColumbiaCrop>& crops, std::shared_ptr<const EyeRegionModel> model, const FitOptions& fit_options,
    const RedirectColumbiaOptions& options,
    const std::function<void(const RedirectColumbiaCase&, const cv::Mat&)>& on_output,
    const std::function<void(int, int)>& progress) {
  // Crops at head pose 0, grouped by subject and eye.
  std::map<std::pair<std::string, char>, std::vector<ColumbiaCrop>> groups;
  int total = 0;
  for (const ColumbiaCrop& crop : crops) {
    if (crop.head_pose != 0) continue;
    groups[{crop.subject, crop.eye}].push_back(crop);
  }
  for (auto& [key, group] : groups) {
    bool has_source = false;
    for (const ColumbiaCrop& crop : group) has_source = has_source || (crop.vertical == 0 && crop.horizontal == 0);
    if (!has_source) group.clear();
    total += static_cast<int>(group.size()) - (has_source ? 1 : 0);
  }

  Fitter fitter(model, fit_options);
  RedirectOptions eyeballs_only;
  eyeballs_only.warp_eyelids = false;
  Redirector full(model), eyeballs(model, eyeballs_only);
  std::vector<RedirectColumbiaCase> cases;
  for (const auto& [key, group] : groups) {
    const auto source = std::find_if(group.begin(), group.end(),
                                     [](const ColumbiaCrop& c) { return c.vertical == 0 && c.horizontal == 0; });
    if (source == group.end()) continue;
    ThrowIfInterrupted();
    const cv::Mat source_image = ReadImage(source->path);
    const int eye = source->ModelEye();
    const FitResult fit = fitter.FitEyePatch(source_image, eye);
    const Camera camera = Fitter::EyePatchCamera(source_image.size());
    full.options().environment = eyeballs.options().environment = -1;
    for (const ColumbiaCrop& target : group) {
      if (&target == &*source) continue;
      const cv::Mat real = ReadImage(target.path);
      if (real.size() != source_image.size()) continue;
      RedirectColumbiaCase result;
      result.source = *source;
      result.target = target;
      result.fit_good = fit.good;
      // Columbia's H is toward the image right at head pose 0: the subject's left, +yaw.
      const GazeTarget offset =
          GazeTarget::Offset(options.angle_scale * target.vertical, options.angle_scale * target.horizontal);
      const Parameters phi = Retarget(fit.phi, offset, options.eyelid_follow);
      cv::Mat only_eyeballs = source_image.clone(), redirected = source_image.clone();
      const RedirectReport a = eyeballs.Redirect(only_eyeballs, camera, fit.phi, phi);
      const RedirectReport b = full.Redirect(redirected, camera, fit.phi, phi);
      eyeballs.options().environment = a.environment;
      full.options().environment = b.environment;
      result.error_none = MeanAbsoluteError(source_image, real);
      result.error_eyeballs = MeanAbsoluteError(only_eyeballs, real);
      result.error_full = MeanAbsoluteError(redirected, real);
      if (on_output) on_output(result, redirected);
      cases.push_back(result);
      if (progress) progress(static_cast<int>(cases.size()), total);
    }
  }
  return cases;
}

}  // namespace gazedirector
