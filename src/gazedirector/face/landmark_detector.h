#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "gazedirector/face/face.h"

namespace gazedirector {

// dlib's 68-point shape predictor (an ensemble of regression trees). Reading
// dlib's model file takes about half a second; Detect is const and thread-safe.
class LandmarkDetector {
 public:
  explicit LandmarkDetector(const std::filesystem::path& model_path);
  ~LandmarkDetector();

  // The model of `model_path`, read from a plain copy of its trees in
  // `cache_dir` when one made from the same file (path, size, time) is there,
  // else from the file, leaving such a copy for the next process (a folder
  // that cannot be written only costs the time).
  static std::shared_ptr<const LandmarkDetector> Load(const std::filesystem::path& model_path,
                                                      const std::filesystem::path& cache_dir);

  // The landmarks of the face in `box` of an 8-bit grayscale image. A face
  // tilted in the image (`roll`, see turned_crop.h) is predicted in an upright
  // crop: the box turned by `roll` about its centre.
  Landmarks68 Detect(const cv::Mat& gray, const cv::Rect2d& box, double roll = 0) const;

 private:
  LandmarkDetector();
  Landmarks68 DetectUpright(const cv::Mat& gray, const cv::Rect2d& box) const;
  bool TryLoadCache(const std::filesystem::path& path, const std::string& fingerprint);
  void SaveCache(const std::filesystem::path& path, const std::string& fingerprint) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gazedirector
