#include "gazedirector/geometry/camera.h"

#include <algorithm>
#include <cmath>

namespace gazedirector {

Camera Camera::Default(int width, int height) {
  const double focal = std::max(width, height);
  return {focal, focal, 0.5 * (width - 1), 0.5 * (height - 1), width, height};
}

Eigen::Matrix3d Camera::K() const {
  Eigen::Matrix3d k;
  k << fx, 0, cx, 0, fy, cy, 0, 0, 1;
  return k;
}

Camera Camera::Scaled(double factor) const {
  // Pixel centres are at integers, so the scaling is about (-0.5, -0.5).
  return {fx * factor,
          fy * factor,
          (cx + 0.5) * factor - 0.5,
          (cy + 0.5) * factor - 0.5,
          static_cast<int>(std::lround(width * factor)),
          static_cast<int>(std::lround(height * factor))};
}

Camera Camera::Resampled(int x0, int y0, int width, int height, int new_width, int new_height) const {
  const double sx = static_cast<double>(new_width) / width, sy = static_cast<double>(new_height) / height;
  return {fx * sx, fy * sy, (cx - x0 + 0.5) * sx - 0.5, (cy - y0 + 0.5) * sy - 0.5, new_width, new_height};
}

Camera Camera::Cropped(double x0, double y0, int new_width, int new_height) const {
  return {fx, fy, cx - x0, cy - y0, new_width, new_height};
}

}  // namespace gazedirector
