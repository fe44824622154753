#include "gazedirector/face/face_detector.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <string>

#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/opencv/cv_image.h>
#include <opencv2/imgproc.hpp>

#include "gazedirector/face/turned_crop.h"
#include "gazedirector/util/thread_pool.h"

namespace gazedirector {

extern const unsigned char kFrontalFaceDetectorBytes[];
extern const std::size_t kFrontalFaceDetectorSize;

namespace {

// The detector's sliding window is 80x80 px; a face box this wide is searched
// at about the window's own scale when verifying a track.
constexpr double kVerifyBoxPixels = 90.0;
constexpr double kVerifyContext = 0.35;  // margin around the box, as a fraction of its size

cv::Rect2d FromDlib(const dlib::rectangle& r, double scale, const cv::Point2d& offset) {
  return {r.left() / scale + offset.x, r.top() / scale + offset.y, (r.width()) / scale, (r.height()) / scale};
}

// A detection in an upright crop, back in the image: same centre, the
// crop's roll, sizes undone of its scale.
Detection FromCrop(const Detection& d, const TurnedCrop& crop) {
  const Eigen::Vector2d centre = crop.ToImage({d.box.x + 0.5 * d.box.width, d.box.y + 0.5 * d.box.height});
  const double w = d.box.width / crop.scale, h = d.box.height / crop.scale;
  return {{centre.x() - 0.5 * w, centre.y() - 0.5 * h, w, h}, d.score, AngleDifference(crop.roll + d.roll, 0)};
}

// dlib's frontal face detector, decoded once per process from the bytes the
// build stored (src/tools/embed_face_detector.cc).
const dlib::frontal_face_detector& StoredFrontalFaceDetector() {
  static const dlib::frontal_face_detector detector = [] {
    dlib::frontal_face_detector decoded;
    std::istringstream stream(std::string(reinterpret_cast<const char*>(kFrontalFaceDetectorBytes), kFrontalFaceDetectorSize));
    dlib::deserialize(decoded, stream);
    return decoded;
  }();
  return detector;
}

}  // namespace

double ConfidenceFromScore(double score) { return 1.0 / (1.0 + std::exp(-3.0 * score)); }

double IntersectionOverUnion(const cv::Rect2d& a, const cv::Rect2d& b) {
  const double intersection = (a & b).area();
  const double united = a.area() + b.area() - intersection;
  return united > 0 ? intersection / united : 0.0;
}

struct FaceDetector::Impl {
  dlib::frontal_face_detector detector = StoredFrontalFaceDetector();  // a copy: its own buffers
  cv::Mat resized;

  std::vector<Detection> Run(const cv::Mat& gray, double scale, double threshold, const cv::Point2d& offset) {
    const cv::Mat* input = &gray;
    if (std::abs(scale - 1.0) > 1e-6) {
      cv::resize(gray, resized, cv::Size(), scale, scale, scale < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
      input = &resized;
    }
    dlib::cv_image<unsigned char> image(*input);
    std::vector<std::pair<double, dlib::rectangle>> found;
    detector(image, found, threshold);
    std::vector<Detection> detections;
    for (const auto& [score, rect] : found) detections.push_back({FromDlib(rect, scale, offset), score});
    std::sort(detections.begin(), detections.end(), [](const Detection& a, const Detection& b) { return a.score > b.score; });
    return detections;
  }
};

FaceDetector::FaceDetector() : impl_(std::make_unique<Impl>()) {}
FaceDetector::~FaceDetector() = default;
FaceDetector::FaceDetector(FaceDetector&&) noexcept = default;
FaceDetector& FaceDetector::operator=(FaceDetector&&) noexcept = default;

std::vector<Detection> FaceDetector::Detect(const cv::Mat& gray, double scale, double threshold) {
  CV_Assert(gray.type() == CV_8UC1);
  return impl_->Run(gray, scale, threshold, {0, 0});
}

std::vector<std::vector<Detection>> FaceDetector::DetectTurned(const cv::Mat& gray, std::span<const double> rolls,
                                                               double scale, double threshold) {
  CV_Assert(gray.type() == CV_8UC1);
  if (!pool_) pool_ = std::make_unique<ThreadPool>();
  while (static_cast<int>(helpers_.size()) + 1 < pool_->size()) helpers_.push_back(std::make_unique<Impl>());
  std::vector<std::vector<Detection>> found(rolls.size());
  pool_->ParallelFor(static_cast<int>(rolls.size()), [&](int i, int worker) {
    Impl& impl = worker == 0 ? *impl_ : *helpers_[worker - 1];
    const TurnedCrop crop = TurnedCrop::WholeImage(gray.size(), rolls[i], scale);
    found[i] = impl.Run(crop.Cut(gray, cv::BORDER_CONSTANT), 1.0, threshold, {0, 0});
    for (Detection& d : found[i]) d = FromCrop(d, crop);
  });
  return found;
}

Detection FaceDetector::Verify(const cv::Mat& gray, const cv::Rect2d& box, double threshold, double roll) {
  CV_Assert(gray.type() == CV_8UC1);
  if (roll != 0) return VerifyTurned(gray, box, threshold, roll);
  const double margin = kVerifyContext * std::max(box.width, box.height);
  cv::Rect window(cv::Point(static_cast<int>(std::floor(box.x - margin)), static_cast<int>(std::floor(box.y - margin))),
                  cv::Point(static_cast<int>(std::ceil(box.br().x + margin)), static_cast<int>(std::ceil(box.br().y + margin))));
  window &= cv::Rect(0, 0, gray.cols, gray.rows);
  Detection best{box, -std::numeric_limits<double>::infinity()};
  if (window.width < 16 || window.height < 16) return best;
  const double scale = std::clamp(kVerifyBoxPixels / std::max(box.width, 1.0), 0.05, 4.0);
  const cv::Mat crop = gray(window);
  for (const Detection& d : impl_->Run(crop, scale, threshold, {double(window.x), double(window.y)})) {
    if (IntersectionOverUnion(d.box, box) >= 0.3 && d.score > best.score) best = d;
  }
  return best;
}

Detection FaceDetector::VerifyTurned(const cv::Mat& gray, const cv::Rect2d& box, double threshold, double roll) {
  const double scale = std::clamp(kVerifyBoxPixels / std::max({box.width, box.height, 1.0}), 0.05, 4.0);
  const TurnedCrop crop = TurnedCrop::AroundBox(box, roll, scale, 1 + 2 * kVerifyContext);
  const cv::Rect2d upright_box = crop.BoxInCrop(box);
  Detection best{box, -std::numeric_limits<double>::infinity(), roll};
  for (const Detection& d : impl_->Run(crop.Cut(gray, cv::BORDER_CONSTANT), 1.0, threshold, {0, 0})) {
    if (IntersectionOverUnion(d.box, upright_box) >= 0.3 && d.score > best.score) best = FromCrop(d, crop);
  }
  return best;
}

}  // namespace gazedirector
