#include "gazedirector/viz/draw_fit.h"

#include <opencv2/imgproc.hpp>

#include "gazedirector/fit/face_fit.h"
#include "gazedirector/render/model_bounds.h"
#include "gazedirector/viz/draw_face.h"

namespace gazedirector {

void DrawFit(cv::Mat& image, const Camera& camera, const Parameters& phi, bool good, std::array<bool, 2> eyes,
             Renderer& renderer, double opacity) {
  renderer.Pose(phi);
  const cv::Rect region = ModelBounds(renderer.posed(), camera, 0.04, eyes);
  if (region.width < 2 || region.height < 2) return;
  const Camera crop = camera.Cropped(region.x, region.y, region.width, region.height);
  RenderBuffers buffers;
  renderer.set_eyes(eyes[0], eyes[1]);
  renderer.Rasterize(crop, buffers);  // posed above
  renderer.Shade(phi, crop, buffers);
  renderer.set_eyes(true, true);

  cv::Mat patch = image(region);
  const cv::Mat rendered = buffers.ColourImage(patch);
  cv::addWeighted(rendered, opacity, patch, 1 - opacity, 0, patch);
  // The outline of what the model covers, so that the fit can be judged.
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(buffers.MaskImage(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  const cv::Scalar colour = good ? cv::Scalar(80, 220, 80) : cv::Scalar(0, 150, 255);
  const int thickness = std::max(1, LineThickness(image) / 2);
  cv::drawContours(patch, contours, -1, colour, thickness, cv::LINE_AA);
  cv::Mat parts = buffers.PartImage(), eyeballs;
  cv::inRange(parts, cv::Scalar(kLeftEyeball), cv::Scalar(kRightEyeball), eyeballs);
  contours.clear();
  cv::findContours(eyeballs, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  cv::drawContours(patch, contours, -1, cv::Scalar(60, 230, 255), thickness, cv::LINE_AA);
  // The fitted irises as far as they show, to hold against the photo's.
  const EyeRegionModel& model = renderer.model();
  const cv::Mat corneas =
      Renderer::InterpolateAttribute(buffers, model, Renderer::CorneaAttribute(model), 1) > 0.5f;
  contours.clear();
  cv::findContours(corneas, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  cv::drawContours(patch, contours, -1, cv::Scalar(255, 200, 40), thickness, cv::LINE_AA);

  const std::array<EyeGaze, 2> gazes = EyeGazes(phi);
  const double length = 1.6 * phi.interocular();
  for (int eye = 0; eye < 2; ++eye) {
    if (!eyes[eye]) continue;
    const Eigen::Vector3d front = gazes[eye].centre + 12.0 * gazes[eye].gaze;  // the cornea
    const Eigen::Vector3d tip = front + length * gazes[eye].gaze;
    if (front.z() <= 1 || tip.z() <= 1) continue;
    const Eigen::Vector2d a = camera.Project(front), b = camera.Project(tip);
    cv::arrowedLine(image, cv::Point2d(a.x(), a.y()), cv::Point2d(b.x(), b.y()), cv::Scalar(40, 40, 255),
                    LineThickness(image) + 1, cv::LINE_AA, 0, 0.15);
  }
}

}  // namespace gazedirector
