#include "gazedirector/face/turned_crop.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include "gazedirector/geometry/rotation.h"

namespace gazedirector {
namespace {

Eigen::Vector2d EyeCentre(const Landmarks68& landmarks, int first) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (int i = first; i < first + 6; ++i) sum += landmarks[i];
  return sum / 6.0;
}

Eigen::Vector2d CropCentre(cv::Size size) { return {0.5 * (size.width - 1), 0.5 * (size.height - 1)}; }

}  // namespace

double LandmarkRoll(const Landmarks68& landmarks) {
  const Eigen::Vector2d across = EyeCentre(landmarks, 42) - EyeCentre(landmarks, 36);
  return std::atan2(across.y(), across.x());
}

double AngleDifference(double a, double b) {
  const double d = std::remainder(a - b, 2 * kPi);
  return d >= kPi ? d - 2 * kPi : d;
}

TurnedCrop TurnedCrop::WholeImage(cv::Size image_size, double roll, double scale) {
  const double c = std::abs(std::cos(roll)), s = std::abs(std::sin(roll));
  const double w = image_size.width, h = image_size.height;
  const cv::Size size(static_cast<int>(std::ceil(scale * (w * c + h * s))),
                      static_cast<int>(std::ceil(scale * (w * s + h * c))));
  return {{0.5 * (w - 1), 0.5 * (h - 1)}, roll, scale, size};
}

TurnedCrop TurnedCrop::AroundBox(const cv::Rect2d& box, double roll, double scale, double extent) {
  const int side = static_cast<int>(std::ceil(extent * scale * std::max({box.width, box.height, 1.0})));
  return {{box.x + 0.5 * box.width, box.y + 0.5 * box.height}, roll, scale, {side, side}};
}

cv::Rect2d TurnedCrop::BoxInCrop(const cv::Rect2d& box) const {
  const Eigen::Vector2d centre = ToCrop({box.x + 0.5 * box.width, box.y + 0.5 * box.height});
  const double w = scale * box.width, h = scale * box.height;
  return {centre.x() - 0.5 * w, centre.y() - 0.5 * h, w, h};
}

Eigen::Vector2d TurnedCrop::ToImage(const Eigen::Vector2d& crop_point) const {
  return Eigen::Vector2d(centre.x, centre.y) + Eigen::Rotation2Dd(roll) * ((crop_point - CropCentre(size)) / scale);
}

Eigen::Vector2d TurnedCrop::ToCrop(const Eigen::Vector2d& image_point) const {
  return CropCentre(size) + scale * (Eigen::Rotation2Dd(-roll) * (image_point - Eigen::Vector2d(centre.x, centre.y)));
}

cv::Mat TurnedCrop::Cut(const cv::Mat& image, int border) const {
  // The crop-to-image map, which warpAffine takes with WARP_INVERSE_MAP.
  const Eigen::Vector2d origin = ToImage(Eigen::Vector2d::Zero());
  const Eigen::Vector2d x_step = ToImage(Eigen::Vector2d::UnitX()) - origin;
  const Eigen::Vector2d y_step = ToImage(Eigen::Vector2d::UnitY()) - origin;
  const cv::Matx23d crop_to_image(x_step.x(), y_step.x(), origin.x(), x_step.y(), y_step.y(), origin.y());
  cv::Mat crop;
  cv::warpAffine(image, crop, crop_to_image, size, cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, border);
  return crop;
}

}  // namespace gazedirector
