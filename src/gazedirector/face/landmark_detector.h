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

  // The landmarks of the face in `box` of an 8-bit grayscale image.
  Landmarks68 Detect(const cv::Mat& gray, const cv::Rect2d& box) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gazedirector
