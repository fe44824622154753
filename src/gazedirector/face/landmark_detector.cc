#include "gazedirector/face/landmark_detector.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <dlib/image_processing/shape_predictor.h>
#include <dlib/opencv/cv_image.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "gazedirector/face/turned_crop.h"
#include "gazedirector/io/atomic_output.h"
#include "gazedirector/io/binary_io.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace fs = std::filesystem;

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

LandmarkDetector::LandmarkDetector() : impl_(std::make_unique<Impl>()) {}
LandmarkDetector::~LandmarkDetector() = default;

namespace {

constexpr char kCacheMagic[8] = {'G', 'D', 'L', 'M', 'K', '0', '0', '1'};
constexpr uint64_t kMaxCount = uint64_t{1} << 28;

std::string ModelFingerprint(const fs::path& model) {
  std::error_code ec;
  return fmt::format("{}|{}|{}", fs::weakly_canonical(model, ec).string(), fs::file_size(model, ec),
                     fs::last_write_time(model, ec).time_since_epoch().count());
}

}  // namespace

std::shared_ptr<const LandmarkDetector> LandmarkDetector::Load(const fs::path& model_path, const fs::path& cache_dir) {
  const std::string fingerprint = ModelFingerprint(model_path);
  const fs::path cache = cache_dir / fmt::format("landmarks_{:016x}.bin", std::hash<std::string>{}(fingerprint));
  std::shared_ptr<LandmarkDetector> cached(new LandmarkDetector());
  if (cached->TryLoadCache(cache, fingerprint)) return cached;
  auto detector = std::make_shared<LandmarkDetector>(model_path);
  try {
    detector->SaveCache(cache, fingerprint);
    spdlog::debug("landmark model cached in {}", cache.string());
  } catch (const Error& e) {
    spdlog::debug("cannot cache the landmark model: {}", e.what());
  }
  return detector;
}

// Per cascade level: the feature pixels' anchors and offsets, then every
// tree's splits and leaves as flat arrays with per-tree counts.
void LandmarkDetector::SaveCache(const fs::path& path, const std::string& fingerprint) const {
  AtomicOutput output(path);
  {
    std::ofstream out(output.temp_path(), std::ios::binary);
    out.write(kCacheMagic, sizeof kCacheMagic);
    WriteVector(out, std::vector<char>(fingerprint.begin(), fingerprint.end()));
    WriteVector(out, std::vector<float>(impl_->initial_shape.begin(), impl_->initial_shape.end()));
    WriteVector(out, std::vector<uint64_t>{impl_->forests.size()});
    for (std::size_t level = 0; level < impl_->forests.size(); ++level) {
      WriteVector(out, std::vector<uint64_t>(impl_->anchor_idx[level].begin(), impl_->anchor_idx[level].end()));
      std::vector<float> deltas;
      for (const auto& d : impl_->deltas[level]) deltas.insert(deltas.end(), {d.x(), d.y()});
      WriteVector(out, deltas);
      std::vector<uint64_t> split_counts, leaf_counts, first, second;
      std::vector<float> thresholds, leaves;
      for (const dlib::impl::regression_tree& tree : impl_->forests[level]) {
        split_counts.push_back(tree.splits.size());
        for (const auto& split : tree.splits) {
          first.push_back(split.idx1), second.push_back(split.idx2), thresholds.push_back(split.thresh);
        }
        leaf_counts.push_back(tree.leaf_values.size());
        for (const auto& leaf : tree.leaf_values) leaves.insert(leaves.end(), leaf.begin(), leaf.end());
      }
      for (const auto* counts : {&split_counts, &first, &second, &leaf_counts}) WriteVector(out, *counts);
      WriteVector(out, thresholds);
      WriteVector(out, leaves);
    }
    if (!out) Fail(ExitCode::kOutput, "cannot write {}", path.string());
  }
  output.Commit();
}

bool LandmarkDetector::TryLoadCache(const fs::path& path, const std::string& fingerprint) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  char magic[sizeof kCacheMagic];
  in.read(magic, sizeof magic);
  if (!in || !std::equal(magic, magic + sizeof magic, kCacheMagic)) return false;
  std::vector<char> stored;
  if (!ReadVector(in, stored, 4096) || std::string(stored.begin(), stored.end()) != fingerprint) return false;
  std::vector<float> initial;
  std::vector<uint64_t> levels;
  if (!ReadVector(in, initial, 1024) || initial.size() != 2 * kNumLandmarks) return false;
  if (!ReadVector(in, levels, 1) || levels.size() != 1 || levels[0] == 0 || levels[0] > 1000) return false;
  impl_->initial_shape.set_size(static_cast<long>(initial.size()));
  std::copy(initial.begin(), initial.end(), impl_->initial_shape.begin());
  impl_->forests.resize(levels[0]);
  impl_->anchor_idx.resize(levels[0]);
  impl_->deltas.resize(levels[0]);
  for (std::size_t level = 0; level < levels[0]; ++level) {
    std::vector<uint64_t> anchors, split_counts, first, second, leaf_counts;
    std::vector<float> deltas, thresholds, leaves;
    if (!ReadVector(in, anchors, kMaxCount) || !ReadVector(in, deltas, kMaxCount) || deltas.size() != 2 * anchors.size() ||
        !ReadVector(in, split_counts, kMaxCount) || !ReadVector(in, first, kMaxCount) ||
        !ReadVector(in, second, kMaxCount) || !ReadVector(in, leaf_counts, kMaxCount) ||
        !ReadVector(in, thresholds, kMaxCount) || !ReadVector(in, leaves, kMaxCount)) {
      return false;
    }
    // A damaged copy must not index outside the feature pixels or the shape.
    const uint64_t pixels = anchors.size();
    const bool inside = std::all_of(anchors.begin(), anchors.end(), [](uint64_t a) { return a < kNumLandmarks; }) &&
                        std::all_of(first.begin(), first.end(), [&](uint64_t i) { return i < pixels; }) &&
                        std::all_of(second.begin(), second.end(), [&](uint64_t i) { return i < pixels; });
    if (!inside || first.size() != second.size() || first.size() != thresholds.size() ||
        split_counts.size() != leaf_counts.size()) {
      return false;
    }
    impl_->anchor_idx[level].assign(anchors.begin(), anchors.end());
    for (std::size_t i = 0; i < anchors.size(); ++i) impl_->deltas[level].emplace_back(deltas[2 * i], deltas[2 * i + 1]);
    std::vector<dlib::impl::regression_tree>& trees = impl_->forests[level];
    trees.resize(split_counts.size());
    std::size_t split = 0, value = 0;
    for (std::size_t t = 0; t < trees.size(); ++t) {
      // dlib's trees are full: one leaf more than splits.
      if (leaf_counts[t] != split_counts[t] + 1 || split + split_counts[t] > first.size() ||
          value + leaf_counts[t] * initial.size() > leaves.size()) {
        return false;
      }
      for (uint64_t s = 0; s < split_counts[t]; ++s, ++split) {
        trees[t].splits.push_back({first[split], second[split], thresholds[split]});
      }
      trees[t].leaf_values.resize(leaf_counts[t]);
      for (auto& leaf : trees[t].leaf_values) {
        leaf.set_size(static_cast<long>(initial.size()));
        std::copy_n(leaves.begin() + static_cast<std::ptrdiff_t>(value), initial.size(), leaf.begin());
        value += initial.size();
      }
    }
    if (split != first.size() || value != leaves.size()) return false;
  }
  return true;
}

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
