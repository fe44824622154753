#include "gazedirector/face/landmark_detector.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <dlib/image_processing/shape_predictor.h>
#include <dlib/opencv/cv_image.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "gazedirector/face/turned_crop.h"
#include "gazedirector/io/atomic_output.h"
#include "gazedirector/io/binary_io.h"
#include "gazedirector/io/mapped_file.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace fs = std::filesystem;

// dlib's shape_predictor rounds its output to whole pixels, which costs
// accuracy and makes video landmarks jitter. The model is read here with
// dlib's own deserialisers and evaluated with dlib's own feature extraction,
// its trees walked as dlib walks them, keeping the sub-pixel positions.
//
// The trees are kept flat, not as dlib's 120,000 leaf vectors: a cached copy
// is mapped and its leaves used where they lie, so a process pages in only the
// leaves its faces reach instead of allocating and copying 65 MB.
struct LandmarkDetector::Impl {
  // One level of the cascade: its feature pixels and its regression trees.
  // Tree t's splits are splits[first_split[t] .. first_split[t + 1]) in
  // dlib's order (node i's children are 2i + 1 and 2i + 2); it has one leaf
  // more than splits, each leaf a shape update of initial_shape.size()
  // values, after the leaves of the trees before it.
  struct Level {
    std::vector<unsigned long> anchor_idx;
    std::vector<dlib::vector<float, 2>> deltas;
    std::vector<dlib::impl::split_feature> splits;
    std::vector<uint64_t> first_split;
    std::span<const float> leaves;  // in owned_leaves or the mapped cache
  };

  dlib::matrix<float, 0, 1> initial_shape;
  std::vector<Level> levels;
  std::vector<std::vector<float>> owned_leaves;
  std::optional<MappedFile> cache;

  void AddTreeUpdates(const Level& level, const std::vector<float>& features, dlib::matrix<float, 0, 1>& shape) const;
};

void LandmarkDetector::Impl::AddTreeUpdates(const Level& level, const std::vector<float>& features,
                                            dlib::matrix<float, 0, 1>& shape) const {
  const std::size_t values = static_cast<std::size_t>(shape.size());
  for (std::size_t t = 0; t + 1 < level.first_split.size(); ++t) {
    const dlib::impl::split_feature* splits = level.splits.data() + level.first_split[t];
    const std::size_t count = level.first_split[t + 1] - level.first_split[t];
    std::size_t node = 0;
    while (node < count) {
      const dlib::impl::split_feature& split = splits[node];
      node = features[split.idx1] - features[split.idx2] > split.thresh ? 2 * node + 1 : 2 * node + 2;
    }
    const float* leaf = level.leaves.data() + (level.first_split[t] + t + node - count) * values;
    for (std::size_t i = 0; i < values; ++i) shape(static_cast<long>(i)) += leaf[i];
  }
}

LandmarkDetector::LandmarkDetector(const std::filesystem::path& model_path) : impl_(std::make_unique<Impl>()) {
  std::ifstream stream(model_path, std::ios::binary);
  if (!stream) Fail(ExitCode::kAssets, "cannot read the landmark model {}", model_path.string());
  std::vector<std::vector<dlib::impl::regression_tree>> forests;
  std::vector<std::vector<unsigned long>> anchor_idx;
  std::vector<std::vector<dlib::vector<float, 2>>> deltas;
  try {
    int version = 0;
    dlib::deserialize(version, stream);
    if (version != 1) Fail(ExitCode::kAssets, "{}: not a dlib shape predictor (version {})", model_path.string(), version);
    dlib::deserialize(impl_->initial_shape, stream);
    dlib::deserialize(forests, stream);
    dlib::deserialize(anchor_idx, stream);
    dlib::deserialize(deltas, stream);
  } catch (const dlib::serialization_error& e) {
    Fail(ExitCode::kAssets, "cannot load the landmark model {}: {}", model_path.string(), e.what());
  }
  const long values = impl_->initial_shape.size();
  const auto not_a_model = [&] { Fail(ExitCode::kAssets, "{} is not a 68-point landmark model", model_path.string()); };
  if (values != 2 * kNumLandmarks || forests.size() != deltas.size() || forests.size() != anchor_idx.size()) {
    not_a_model();
  }
  impl_->levels.reserve(forests.size());
  impl_->owned_leaves.reserve(forests.size());
  for (std::size_t l = 0; l < forests.size(); ++l) {
    Impl::Level& level = impl_->levels.emplace_back();
    level.anchor_idx = std::move(anchor_idx[l]);
    level.deltas = std::move(deltas[l]);
    std::vector<float>& leaves = impl_->owned_leaves.emplace_back();
    level.first_split.push_back(0);
    for (const dlib::impl::regression_tree& tree : forests[l]) {
      // dlib's trees are full: one leaf more than splits.
      if (tree.leaf_values.size() != tree.splits.size() + 1) not_a_model();
      level.splits.insert(level.splits.end(), tree.splits.begin(), tree.splits.end());
      level.first_split.push_back(level.splits.size());
      for (const auto& leaf : tree.leaf_values) {
        if (leaf.size() != values) not_a_model();
        leaves.insert(leaves.end(), leaf.begin(), leaf.end());
      }
    }
    level.leaves = leaves;
  }
}

LandmarkDetector::LandmarkDetector() : impl_(std::make_unique<Impl>()) {}
LandmarkDetector::~LandmarkDetector() = default;

namespace {

constexpr char kCacheMagic[8] = {'G', 'D', 'L', 'M', 'K', '0', '0', '2'};
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

// Per cascade level: the feature pixels' anchors and offsets, each tree's
// first split, the splits' pixel pairs and thresholds, then the leaves,
// aligned to be used where they lie in the mapped file.
void LandmarkDetector::SaveCache(const fs::path& path, const std::string& fingerprint) const {
  AtomicOutput output(path);
  {
    std::ofstream out(output.temp_path(), std::ios::binary);
    out.write(kCacheMagic, sizeof kCacheMagic);
    WriteVector(out, std::vector<char>(fingerprint.begin(), fingerprint.end()));
    WriteVector(out, std::vector<float>(impl_->initial_shape.begin(), impl_->initial_shape.end()));
    WriteVector(out, std::vector<uint64_t>{impl_->levels.size()});
    for (const Impl::Level& level : impl_->levels) {
      WriteVector(out, std::vector<uint64_t>(level.anchor_idx.begin(), level.anchor_idx.end()));
      std::vector<float> deltas;
      for (const auto& d : level.deltas) deltas.insert(deltas.end(), {d.x(), d.y()});
      WriteVector(out, deltas);
      std::vector<uint64_t> first, second;
      std::vector<float> thresholds;
      for (const auto& split : level.splits) {
        first.push_back(split.idx1), second.push_back(split.idx2), thresholds.push_back(split.thresh);
      }
      WriteVector(out, level.first_split);
      WriteVector(out, first);
      WriteVector(out, second);
      WriteVector(out, thresholds);
      WriteAlignedVector(out, std::vector<float>(level.leaves.begin(), level.leaves.end()));
    }
    if (!out) Fail(ExitCode::kOutput, "cannot write {}", path.string());
  }
  output.Commit();
}

bool LandmarkDetector::TryLoadCache(const fs::path& path, const std::string& fingerprint) {
  std::optional<MappedFile> file = MappedFile::Open(path);
  if (!file) return false;
  std::span<const std::byte> rest = file->bytes();
  if (rest.size() < sizeof kCacheMagic || std::memcmp(rest.data(), kCacheMagic, sizeof kCacheMagic) != 0) return false;
  rest = rest.subspan(sizeof kCacheMagic);
  std::vector<char> stored;
  if (!ReadVector(rest, stored, 4096) || std::string(stored.begin(), stored.end()) != fingerprint) return false;
  std::vector<float> initial;
  std::vector<uint64_t> levels;
  if (!ReadVector(rest, initial, 1024) || initial.size() != 2 * kNumLandmarks) return false;
  if (!ReadVector(rest, levels, 1) || levels.size() != 1 || levels[0] == 0 || levels[0] > 1000) return false;
  impl_->initial_shape.set_size(static_cast<long>(initial.size()));
  std::copy(initial.begin(), initial.end(), impl_->initial_shape.begin());
  impl_->levels.resize(levels[0]);
  for (Impl::Level& level : impl_->levels) {
    std::vector<uint64_t> anchors, first, second;
    std::vector<float> deltas, thresholds;
    if (!ReadVector(rest, anchors, kMaxCount) || !ReadVector(rest, deltas, kMaxCount) ||
        deltas.size() != 2 * anchors.size() || !ReadVector(rest, level.first_split, kMaxCount) ||
        !ReadVector(rest, first, kMaxCount) || !ReadVector(rest, second, kMaxCount) ||
        !ReadVector(rest, thresholds, kMaxCount) || !ViewAlignedVector(rest, level.leaves, kMaxCount)) {
      return false;
    }
    // A damaged copy must not index outside the feature pixels, the splits or the leaves.
    const uint64_t pixels = anchors.size();
    const bool inside = std::all_of(anchors.begin(), anchors.end(), [](uint64_t a) { return a < kNumLandmarks; }) &&
                        std::all_of(first.begin(), first.end(), [&](uint64_t i) { return i < pixels; }) &&
                        std::all_of(second.begin(), second.end(), [&](uint64_t i) { return i < pixels; });
    const std::vector<uint64_t>& bounds = level.first_split;
    const std::size_t trees = bounds.empty() ? 0 : bounds.size() - 1;
    if (!inside || first.size() != second.size() || first.size() != thresholds.size() || bounds.empty() ||
        bounds.front() != 0 || !std::is_sorted(bounds.begin(), bounds.end()) || bounds.back() != first.size() ||
        level.leaves.size() != (first.size() + trees) * initial.size()) {
      return false;
    }
    level.anchor_idx.assign(anchors.begin(), anchors.end());
    for (std::size_t i = 0; i < anchors.size(); ++i) level.deltas.emplace_back(deltas[2 * i], deltas[2 * i + 1]);
    for (std::size_t i = 0; i < first.size(); ++i) level.splits.push_back({first[i], second[i], thresholds[i]});
  }
  impl_->cache = std::move(file);
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
  for (const Impl::Level& level : impl_->levels) {
    dlib::impl::extract_feature_pixel_values(image, rect, shape, impl_->initial_shape, level.anchor_idx, level.deltas,
                                             features);
    impl_->AddTreeUpdates(level, features, shape);
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
