#pragma once

#include <Eigen/Core>

namespace gazedirector {

// A pinhole camera in OpenCV's convention: x right, y down, z forward; pixel
// centres at integer coordinates. Units of 3D points are millimetres.
struct Camera {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;

  // The default when intrinsics are unknown: fx = fy = max(width, height)
  // (a 53 degree field of view across the longer side, typical of webcams and
  // phones) and the principal point at the image centre.
  static Camera Default(int width, int height);

  bool operator==(const Camera&) const = default;

  Eigen::Vector2d Project(const Eigen::Vector3d& point) const {
    return {fx * point.x() / point.z() + cx, fy * point.y() / point.z() + cy};
  }
  // The unit ray through a pixel.
  Eigen::Vector3d Ray(const Eigen::Vector2d& pixel) const {
    return Eigen::Vector3d((pixel.x() - cx) / fx, (pixel.y() - cy) / fy, 1.0).normalized();
  }
  Eigen::Matrix3d K() const;
  // The same camera for an image scaled by `factor` and cropped at (x0, y0).
  Camera Scaled(double factor) const;
  Camera Cropped(double x0, double y0, int new_width, int new_height) const;
  // The camera of the image region `x0, y0, width, height` resized to
  // `new_width` x `new_height` (pixel centres map as cv::resize maps them).
  Camera Resampled(int x0, int y0, int width, int height, int new_width, int new_height) const;
  // A point of this camera's image in the resampled image, and back.
  static Eigen::Vector2d ToResampled(const Eigen::Vector2d& p, int x0, int y0, double sx, double sy) {
    return {(p.x() - x0 + 0.5) * sx - 0.5, (p.y() - y0 + 0.5) * sy - 0.5};
  }
};

}  // namespace gazedirector
