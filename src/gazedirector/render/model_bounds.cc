#include "gazedirector/render/model_bounds.h"

#include <algorithm>
#include <cmath>

namespace gazedirector {

namespace {

// The pixels from `low` to `high` (image coordinates) grown by `grow` on each
// side, clipped to the image.
cv::Rect PixelsCovering(const Eigen::Vector2d& low, const Eigen::Vector2d& high, const Eigen::Vector2d& grow,
                        const Camera& camera) {
  const double x0 = std::max(-1e6, low.x() - grow.x()), y0 = std::max(-1e6, low.y() - grow.y());
  const double x1 = std::min(1e6, high.x() + grow.x()), y1 = std::min(1e6, high.y() + grow.y());
  cv::Rect region(cv::Point(static_cast<int>(std::floor(x0)), static_cast<int>(std::floor(y0))),
                  cv::Point(static_cast<int>(std::ceil(x1)), static_cast<int>(std::ceil(y1))));
  return region & cv::Rect(0, 0, camera.width, camera.height);
}

}  // namespace

cv::Rect ModelBounds(const PosedModel& posed, const Camera& camera, double margin, std::array<bool, 2> eyes) {
  Eigen::Vector2d low(1e9, 1e9), high(-1e9, -1e9);
  for (int eye = 0; eye < 2; ++eye) {
    if (!eyes[eye]) continue;
    for (Eigen::Index v = 0; v < posed.region[eye].cols(); ++v) {
      const Eigen::Vector3d p = posed.eyes[eye].region_to_camera * posed.region[eye].col(v) + posed.eyes[eye].centre;
      if (p.z() <= 1) return {};
      const Eigen::Vector2d q = camera.Project(p);
      low = low.cwiseMin(q), high = high.cwiseMax(q);
    }
  }
  if (low.x() > high.x()) return {};
  return PixelsCovering(low, high, margin * (high - low), camera);
}

cv::Rect EyeballBounds(const PosedModel& posed, const Camera& camera) {
  Eigen::Vector2d low(1e9, 1e9), high(-1e9, -1e9);
  for (int part : {kLeftEyeball, kRightEyeball}) {
    const Eigen::Matrix3Xf& positions = posed.parts[part].positions;
    for (Eigen::Index v = 0; v < positions.cols(); ++v) {
      if (positions(2, v) <= 1) return {};
      const Eigen::Vector2d q = camera.Project(positions.col(v).cast<double>());
      low = low.cwiseMin(q), high = high.cwiseMax(q);
    }
  }
  if (low.x() > high.x()) return {};
  return PixelsCovering(low, high, Eigen::Vector2d::Ones(), camera);
}

}  // namespace gazedirector
