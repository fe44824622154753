#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "gazedirector/face/face.h"

namespace gazedirector {

// Faces tilted in the image's plane (a head leaning over, a camera held
// askew) are searched for and landmarked in an upright crop: HOG's detector
// and the landmark predictor were trained on upright faces and fail beyond
// about 30-40 degrees.
//
// Roll is the angle from the image's x axis to the face's own x axis (from the
// image-left eye to the image-right eye of an upright face), in radians,
// positive turning x toward y (clockwise as the image is shown).

// The face's roll as its landmarks show it: the line between the eyes' centres.
double LandmarkRoll(const Landmarks68& landmarks);

// The angle a - b wrapped to [-pi, pi).
double AngleDifference(double a, double b);

// A square or rectangular crop of an image, turned by `roll` about `centre`
// and scaled by `scale` (crop pixels per image pixel): a face at that roll
// stands upright in it.
struct TurnedCrop {
  cv::Point2d centre;  // image point at the crop's centre
  double roll = 0;
  double scale = 1;
  cv::Size size;

  // The smallest crop that holds the whole image turned by `roll`.
  static TurnedCrop WholeImage(cv::Size image_size, double roll, double scale);
  // A square crop centred on `box`, `extent` times its larger side across.
  static TurnedCrop AroundBox(const cv::Rect2d& box, double roll, double scale, double extent);

  // An image box as it stands in the crop (same centre, sizes scaled): the
  // box turned by `roll` about its centre, made upright.
  cv::Rect2d BoxInCrop(const cv::Rect2d& box) const;

  Eigen::Vector2d ToImage(const Eigen::Vector2d& crop_point) const;
  Eigen::Vector2d ToCrop(const Eigen::Vector2d& image_point) const;
  // The crop's pixels (bilinear). Where the crop reaches past the image, the
  // image is reflected at its border by default; a detector searching the crop
  // needs `cv::BORDER_CONSTANT` instead, or it finds the reflected faces.
  cv::Mat Cut(const cv::Mat& image, int border = cv::BORDER_REFLECT_101) const;
};

}  // namespace gazedirector
