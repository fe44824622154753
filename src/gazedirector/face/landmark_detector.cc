#include "gazedirector/face/landmark_detector.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <vector>

#include <dlib/image_processing/shape_predictor.h>
#include <dlib/opencv/cv_image.h>

#include "gazedirector/face/turned_crop.h"
#include "gazedirector/util/error.h"

namespace gazedirector {

// dlib's shape_predictor rounds its output to whole pixels, which costs
// accuracy and makes video landmarks jitter. The model is read here with
// dlib's own deserialisers into the same parts and evaluated with dlib's own
// feature extraction and trees, keeping the sub-pixel positions.
struct LandmarkDetector::Impl {
  dlib::matrix<float, 0, 1> initial_shape;
  std::vector<std::vector<dlib::impl::regression_tree>> forests;
  std::vector<std::vector<unsigned long>> anchor_idx;
  std::vector<std::vector<dlib::vector<float, 2>>> deltas;
};

LandmarkDetector::LandmarkDetector(const std::filesystem::path& model_path) : impl_(std::make_unique<Impl>()) {
  std::ifstream stream(model_path, std::ios::binary);
  if (!stream) Fail(ExitCode::kAssets, "cannot read the landmark model {}", model_path.string());
  try {
    int version = 0;
    dlib::deserialize(version, stream);
    if (version != 1) Fail(ExitCode::kAssets, "{}: not a dlib shape predictor (version {})", model_path.string(), version);
    dlib::deserialize(impl_->initial_shape, stream);
    dlib::deserialize(impl_->forests, stream);
    dlib::deserialize(impl_->anchor_idx, stream);
    dlib::deserialize(impl_->deltas, stream);
  } catch (const dlib::serialization_error& e) {
    Fail(ExitCode::kAssets, "cannot load the landmark model {}: {}", model_path.string(), e.what());
  }
  if (impl_->initial_shape.size() != 2 * kNumLandmarks || impl_->forests.size() != impl_->deltas.size()) {
    Fail(ExitCode::kAssets, "{} is not a 68-point landmark model", model_path.string());
  }
}

LandmarkDetector::~LandmarkDetector() = default;

Landmarks68 LandmarkDetector::Detect(const cv::Mat& gray, const cv::Rect2d& box, double roll) const {
  CV_Assert(gray.type() == CV_8UC1);
  if (roll == 0) return DetectUpright(gray, box);
  // The trees sample pixels up to about half a box beyond the box; a large
  // face is cut at no more than kMaxSide pixels across, which keeps the cut cheap.
  constexpr double kMaxSide = 320;
  const double scale = std::min(1.0, kMaxSide / std::max({box.width, box.height, 1.0}));
  const TurnedCrop crop = TurnedCrop::AroundBox(box, roll, scale, 2.0);
  Landmarks68 landmarks = DetectUpright(crop.Cut(gray), crop.BoxInCrop(box));
  for (auto& p : landmarks) p = crop.ToImage(p);
  return landmarks;
}

Landmarks68 LandmarkDetector::DetectUpright(const cv::Mat& gray, const cv::Rect2d& box) const {
  const dlib::cv_image<unsigned char> image(gray);
  const dlib::rectangle rect(std::lround(box.x), std::lround(box.y), std::lround(box.x + box.width - 1),
                             std::lround(box.y + box.height - 1));
  dlib::matrix<float, 0, 1> shape = impl_->initial_shape;
  std::vector<float> features;
  for (std::size_t level = 0; level < impl_->forests.size(); ++level) {
    dlib::impl::extract_feature_pixel_values(image, rect, shape, impl_->initial_shape, impl_->anchor_idx[level],
                                             impl_->deltas[level], features);
    unsigned long leaf = 0;
    for (const auto& tree : impl_->forests[level]) shape += tree(features, leaf);
  }
  const dlib::point_transform_affine to_image = dlib::impl::unnormalizing_tform(rect);
  Landmarks68 landmarks;
  for (int i = 0; i < kNumLandmarks; ++i) {
    const dlib::vector<double, 2> p = to_image(dlib::impl::location(shape, i));
    landmarks[i] = Eigen::Vector2d(p.x(), p.y());
  }
  return landmarks;
}

}  // namespace gazedirector
