#pragma once

#include <filesystem>
#include <memory>

#include <opencv2/core.hpp>

#include "gazedirector/face/face.h"

namespace gazedirector {

// dlib's 68-point shape predictor (an ensemble of regression trees). Loading
// the model takes about half a second; Detect is const and thread-safe.
class LandmarkDetector {
 public:
  explicit LandmarkDetector(const std::filesystem::path& model_path);
  ~LandmarkDetector();

  // The landmarks of the face in `box` of an 8-bit grayscale image. A face
  // tilted in the image (`roll`, see turned_crop.h) is predicted in an upright
  // crop: the box turned by `roll` about its centre.
  Landmarks68 Detect(const cv::Mat& gray, const cv::Rect2d& box, double roll = 0) const;

 private:
  Landmarks68 DetectUpright(const cv::Mat& gray, const cv::Rect2d& box) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gazedirector
