#include "gazedirector/render/limbus_distance.h"

#include <array>
#include <cmath>

#include "gazedirector/model/eye_region_topology.h"

namespace gazedirector {
namespace {

// Per vertex of each posed eyeball: how far its texture coordinate is from
// the iris's centre, in limbus radii (1 on the iris's edge).
std::array<Eigen::MatrixXf, kNumParts> LimbusRadii(const PosedModel& posed) {
  std::array<Eigen::MatrixXf, kNumParts> radii;
  for (int part : {kLeftEyeball, kRightEyeball}) {
    const Eigen::Matrix2Xf& uvs = posed.parts[part].uvs;
    radii[part] = (uvs.array() - 0.5f).matrix().colwise().norm() / static_cast<float>(topology::kLimbusUvRadius);
  }
  return radii;
}

}  // namespace

cv::Mat LimbusDistance(const RenderBuffers& buffers, const EyeRegionModel& model, const PosedModel& posed) {
  const cv::Mat radius = Renderer::InterpolateAttribute(buffers, model, LimbusRadii(posed), 1);
  const int width = buffers.width(), height = buffers.height();
  cv::Mat distance(height, width, CV_32F, cv::Scalar(kFarFromLimbus));
  // The radius's change per pixel along one axis: central where both
  // neighbours show the same eyeball, one-sided where one does.
  auto slope = [&](int pixel, int x, int y, int dx, int dy) {
    const int part = buffers.PartAt(pixel);
    const bool before = x - dx >= 0 && y - dy >= 0 && buffers.PartAt(pixel - dx - dy * width) == part;
    const bool after = x + dx < width && y + dy < height && buffers.PartAt(pixel + dx + dy * width) == part;
    const float here = radius.at<float>(y, x);
    if (before && after) return 0.5f * (radius.at<float>(y + dy, x + dx) - radius.at<float>(y - dy, x - dx));
    if (after) return radius.at<float>(y + dy, x + dx) - here;
    if (before) return here - radius.at<float>(y - dy, x - dx);
    return 0.0f;
  };
  for (int pixel : buffers.foreground) {
    if (!IsEyeball(buffers.PartAt(pixel))) continue;
    const int x = pixel % width, y = pixel / width;
    const float beyond = radius.at<float>(y, x) - 1;
    const float gradient = std::hypot(slope(pixel, x, y, 1, 0), slope(pixel, x, y, 0, 1));
    distance.at<float>(y, x) = gradient > 1e-6f ? beyond / gradient : std::copysign(kFarFromLimbus, beyond);
  }
  return distance;
}

}  // namespace gazedirector
