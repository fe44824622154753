#include "gazedirector/eval/redirect_columbia.h"

#include <map>
#include <tuple>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "gazedirector/io/image_io.h"
#include "gazedirector/redirect/gaze_target.h"
#include "gazedirector/redirect/redirector.h"
#include "gazedirector/render/renderer.h"
#include "gazedirector/util/interrupt.h"

namespace gazedirector {

double MeanAbsoluteError(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat difference;
  cv::absdiff(a, b, difference);
  const cv::Scalar sum = cv::sum(difference);
  return (sum[0] + sum[1] + sum[2]) / (static_cast<double>(a.total()) * a.channels());
}

cv::Point2f RegisterOnSkin(const cv::Mat& source, const cv::Mat& real, const cv::Rect& eye) {
  cv::Mat template_grey, real_grey;
  cv::cvtColor(source, template_grey, cv::COLOR_BGR2GRAY);
  cv::cvtColor(real, real_grey, cv::COLOR_BGR2GRAY);
  template_grey.convertTo(template_grey, CV_32F);
  real_grey.convertTo(real_grey, CV_32F);
  cv::Mat skin(source.size(), CV_8UC1, cv::Scalar(255));
  skin(eye & cv::Rect(0, 0, source.cols, source.rows)).setTo(0);
  cv::Mat warp = cv::Mat::eye(2, 3, CV_32F);
  try {
    const cv::TermCriteria until(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-5);
    cv::findTransformECC(template_grey, real_grey, warp, cv::MOTION_TRANSLATION, until, skin, 1);
  } catch (const cv::Exception&) {
    return {0, 0};  // ECC did not converge: compare unregistered
  }
  const cv::Point2f shift(warp.at<float>(0, 2), warp.at<float>(1, 2));
  // A crop's framing wanders by a few pixels; more is a failed estimate.
  return std::hypot(shift.x, shift.y) <= 0.15f * source.cols ? shift : cv::Point2f(0, 0);
}

cv::Mat Shifted(const cv::Mat& image, cv::Point2f shift) {
  if (shift == cv::Point2f(0, 0)) return image;
  const cv::Matx23f back(1, 0, -shift.x, 0, 1, -shift.y);  // out(x) = image(x - shift)
  cv::Mat out;
  cv::warpAffine(image, out, back, image.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
  return out;
}

namespace {

// The fitted eye opening, widened to the lids and the crease above it, which
// move with the gaze.
cv::Rect EyeBox(const Parameters& phi, std::shared_ptr<const EyeRegionModel> model, const Camera& camera, int eye) {
  Renderer renderer(model);
  renderer.set_eyes(eye == kLeftEye, eye == kRightEye);
  RenderBuffers buffers;
  renderer.Render(phi, camera, buffers);
  const cv::Mat eyeball = buffers.EyeballMaskImage();
  if (cv::countNonZero(eyeball) == 0) return {};
  const cv::Rect box = cv::boundingRect(eyeball);
  const int side = box.width / 8, above = box.height * 3 / 4, below = box.height / 2;
  return {box.x - side, box.y - above, box.width + 2 * side, box.height + above + below};
}

}  // namespace

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
    const cv::Rect eye_box = EyeBox(fit.phi, model, camera, eye);
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
      if (options.register_crops) result.shift = RegisterOnSkin(source_image, real, eye_box);
      result.error_none = MeanAbsoluteError(Shifted(source_image, result.shift), real);
      result.error_eyeballs = MeanAbsoluteError(Shifted(only_eyeballs, result.shift), real);
      result.error_full = MeanAbsoluteError(Shifted(redirected, result.shift), real);
      if (on_output) on_output(result, redirected);
      cases.push_back(result);
      if (progress) progress(static_cast<int>(cases.size()), total);
    }
  }
  return cases;
}

}  // namespace gazedirector
