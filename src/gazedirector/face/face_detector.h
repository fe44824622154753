#pragma once

#include <memory>
#include <span>
#include <vector>

#include <opencv2/core.hpp>

namespace gazedirector {

class ThreadPool;

struct Detection {
  cv::Rect2d box;  // in the coordinates of the image given to Detect
  double score = 0;  // the HOG detector's margin; faces score >= 0
  double roll = 0;   // the face stands upright in `box` turned by `roll` about its centre (turned_crop.h)
};

// The detector's score mapped to [0, 1]: 0.5 at the detection threshold.
double ConfidenceFromScore(double score);

// dlib's HOG + linear SVM frontal face detector. Not thread-safe: use one per
// thread.
class FaceDetector {
 public:
  FaceDetector();
  ~FaceDetector();
  FaceDetector(FaceDetector&&) noexcept;
  FaceDetector& operator=(FaceDetector&&) noexcept;

  // Faces in an 8-bit grayscale image, searched after resizing it by `scale`
  // (upsampling finds faces smaller than the detector's 80 px window).
  // Detections scoring below `threshold` are dropped; best first.
  std::vector<Detection> Detect(const cv::Mat& gray, double scale = 1.0, double threshold = 0.0);

  // Faces that stand upright in the image turned by each of `rolls` (radians,
  // see turned_crop.h): one list per roll, best first. The searches run side
  // by side on the hardware's threads, each with its own copy of the detector.
  std::vector<std::vector<Detection>> DetectTurned(const cv::Mat& gray, std::span<const double> rolls,
                                                   double scale = 1.0, double threshold = 0.0);

  // The best score of a face overlapping `box` (IoU >= 0.3), searched in a
  // small window around it: a cheap check that a tracked face is still there.
  // Its score is -infinity when nothing scores above `threshold`. A tilted
  // face (`roll`) is searched for in an upright crop.
  Detection Verify(const cv::Mat& gray, const cv::Rect2d& box, double threshold = -1.0, double roll = 0);

 private:
  Detection VerifyTurned(const cv::Mat& gray, const cv::Rect2d& box, double threshold, double roll);

  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::unique_ptr<ThreadPool> pool_;            // made at the first turned search
  std::vector<std::unique_ptr<Impl>> helpers_;  // the pool's other threads' detectors
};

double IntersectionOverUnion(const cv::Rect2d& a, const cv::Rect2d& b);

}  // namespace gazedirector
