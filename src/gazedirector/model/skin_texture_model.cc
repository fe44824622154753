#include "gazedirector/model/skin_texture_model.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "gazedirector/io/atomic_output.h"
#include "gazedirector/io/binary_io.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/timer.h"

namespace gazedirector {
namespace fs = std::filesystem;
namespace {

constexpr char kCacheMagic[8] = {'G', 'D', 'S', 'K', 'I', 'N', '0', '2'};
constexpr int kChannels = 3;

// Fills texels where `valid` is 0 with the average of their valid neighbours,
// growing inward until none is left (the eye hole of the skin maps).
void FillHoles(cv::Mat& rgb, cv::Mat& valid) {
  for (int pass = 0; pass < 4 * rgb.rows; ++pass) {
    cv::Mat next_valid = valid.clone();
    bool any_missing = false;
    for (int y = 0; y < rgb.rows; ++y) {
      for (int x = 0; x < rgb.cols; ++x) {
        if (valid.at<uchar>(y, x)) continue;
        any_missing = true;
        cv::Vec3f sum(0, 0, 0);
        int count = 0;
        for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= rgb.cols || ny >= rgb.rows || !valid.at<uchar>(ny, nx)) continue;
          sum += rgb.at<cv::Vec3f>(ny, nx);
          ++count;
        }
        if (count > 0) {
          rgb.at<cv::Vec3f>(y, x) = sum / count;
          next_valid.at<uchar>(y, x) = 1;
        }
      }
    }
    valid = next_valid;
    if (!any_missing) return;
  }
}

std::string Fingerprint(const std::vector<fs::path>& files, int num_modes) {
  std::string text = fmt::format("v2|{}|{}", SkinTextureModel::kSize, num_modes);
  for (const fs::path& file : files) {
    std::error_code ec;
    text += fmt::format("|{}:{}:{}", file.filename().string(), fs::file_size(file, ec),
                        fs::last_write_time(file, ec).time_since_epoch().count());
  }
  return std::to_string(std::hash<std::string>{}(text));
}

std::vector<fs::path> SkinMaps(const fs::path& skin_dir) {
  std::vector<fs::path> maps;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(skin_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > 10 && name.ends_with("_color.png")) maps.push_back(entry.path());
  }
  std::sort(maps.begin(), maps.end());
  if (maps.size() < 2) Fail(ExitCode::kAssets, "{}: expected the 20 scanned skin maps (*_color.png)", skin_dir.string());
  return maps;
}

fs::path LookDownOf(const fs::path& map) {
  std::string name = map.filename().string();
  name.replace(name.size() - 4, 4, "_look_down.png");
  return map.parent_path() / name;
}

}  // namespace

std::vector<float> SkinTextureModel::LoadSkinMap(const fs::path& path, int size) {
  const cv::Mat bgr = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (bgr.empty()) Fail(ExitCode::kAssets, "cannot read the skin map {}", path.string());
  cv::Mat rgb, valid;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  rgb.convertTo(rgb, CV_32FC3, 1.0 / 255.0);
  cv::Mat gray;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  cv::Mat hole = gray == 0;
  cv::Mat weight;
  cv::bitwise_not(hole, weight);
  weight.convertTo(weight, CV_32F, 1.0 / 255.0);
  // Average only valid texels when downsampling, so the hole does not bleed.
  cv::Mat weighted, small, small_weight;
  cv::Mat weight3;
  cv::merge(std::vector<cv::Mat>{weight, weight, weight}, weight3);
  cv::multiply(rgb, weight3, weighted);
  cv::resize(weighted, small, cv::Size(size, size), 0, 0, cv::INTER_AREA);
  cv::resize(weight, small_weight, cv::Size(size, size), 0, 0, cv::INTER_AREA);
  cv::Mat valid_small = small_weight > 0.5;
  valid_small /= 255;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const float w = small_weight.at<float>(y, x);
      if (w > 1e-3f) small.at<cv::Vec3f>(y, x) /= w;
    }
  }
  FillHoles(small, valid_small);
  std::vector<float> texels(static_cast<std::size_t>(size) * size * kChannels);
  std::memcpy(texels.data(), small.ptr<float>(), texels.size() * sizeof(float));
  return texels;
}

SkinTextureModel SkinTextureModel::Build(const fs::path& skin_dir, int num_modes) {
  Timer timer;
  const std::vector<fs::path> maps = SkinMaps(skin_dir);
  const int n = static_cast<int>(maps.size());
  if (num_modes >= n) Fail(ExitCode::kAssets, "{} skin maps give at most {} texture modes", n, n - 1);
  const std::size_t plane = static_cast<std::size_t>(kSize) * kSize * kChannels;
  const std::size_t dimension = 2 * plane;

  SkinTextureModel model;
  // The uv footprint of the mesh, from the layout picture's alpha channel.
  cv::Mat layout = cv::imread((skin_dir / "face_uvs.png").string(), cv::IMREAD_UNCHANGED);
  if (layout.empty() || layout.channels() != 4) Fail(ExitCode::kAssets, "{}: face_uvs.png with alpha expected", skin_dir.string());
  cv::Mat alpha, small_alpha;
  cv::extractChannel(layout, alpha, 3);
  cv::resize(alpha, small_alpha, cv::Size(kSize, kSize), 0, 0, cv::INTER_AREA);
  model.footprint_.resize(static_cast<std::size_t>(kSize) * kSize);
  for (int i = 0; i < kSize * kSize; ++i) model.footprint_[i] = small_alpha.data[i] > 16 ? 1.0f : 0.0f;

  Eigen::MatrixXf data(dimension, n);
  for (int i = 0; i < n; ++i) {
    const std::vector<float> ahead = LoadSkinMap(maps[i], kSize);
    const std::vector<float> down = LoadSkinMap(LookDownOf(maps[i]), kSize);
    std::copy(ahead.begin(), ahead.end(), data.col(i).data());
    std::copy(down.begin(), down.end(), data.col(i).data() + plane);
    std::string name = maps[i].filename().string();
    model.subject_names_.push_back(name.substr(0, name.find('_')));
  }
  const Eigen::VectorXf mean = data.rowwise().mean();
  Eigen::MatrixXf centred = data.colwise() - mean;
  for (std::size_t t = 0; t < dimension; ++t) {
    if (model.footprint_[(t % plane) / kChannels] == 0.0f) centred.row(static_cast<Eigen::Index>(t)).setZero();
  }
  const Eigen::MatrixXd gram = (centred.transpose() * centred).cast<double>();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(gram);
  model.mean_[kAhead].assign(mean.data(), mean.data() + plane);
  model.mean_[kLookDown].assign(mean.data() + plane, mean.data() + dimension);
  model.coefficients_.assign(n, std::vector<double>(num_modes));
  model.modes_.resize(num_modes);
  for (int j = 0; j < num_modes; ++j) {
    const int column = n - 1 - j;  // eigenvalues ascend
    const double variance = std::max(solver.eigenvalues()[column], 0.0) / (n - 1);
    const Eigen::VectorXf direction = (centred * solver.eigenvectors().col(column).cast<float>()).normalized();
    const double sigma = std::sqrt(variance);
    model.stddev_.push_back(sigma);
    const Eigen::VectorXf scaled = direction * static_cast<float>(sigma);
    model.modes_[j][kAhead].assign(scaled.data(), scaled.data() + plane);
    model.modes_[j][kLookDown].assign(scaled.data() + plane, scaled.data() + dimension);
    for (int i = 0; i < n; ++i) model.coefficients_[i][j] = centred.col(i).dot(direction) / sigma;
  }
  spdlog::debug("built the skin texture PCA from {} maps in {:.1f} s", n, timer.Seconds());
  return model;
}

void SkinTextureModel::Compose(const double* tau, RgbaTexture& ahead, RgbaTexture& look_down) const {
  const std::size_t texels = static_cast<std::size_t>(kSize) * kSize;
  RgbaTexture* targets[2] = {&ahead, &look_down};
  for (int variant = 0; variant < 2; ++variant) {
    RgbaTexture& target = *targets[variant];
    if (target.empty() || target.size() != kSize) target.Resize(kSize);
    float* out = target.data();
    const float* mean = mean_[variant].data();
    for (std::size_t t = 0; t < texels; ++t) {
      out[4 * t] = mean[3 * t], out[4 * t + 1] = mean[3 * t + 1], out[4 * t + 2] = mean[3 * t + 2], out[4 * t + 3] = 0;
    }
    for (int j = 0; j < num_modes(); ++j) {
      const float weight = static_cast<float>(tau[j]);
      if (weight == 0.0f) continue;
      const float* mode = modes_[j][variant].data();
      for (std::size_t t = 0; t < texels; ++t) {
        for (int c = 0; c < 3; ++c) out[4 * t + c] += weight * mode[3 * t + c];
      }
    }
    target.BuildMips();
  }
}

void SkinTextureModel::Save(const fs::path& path, const std::string& fingerprint) const {
  AtomicOutput output(path);
  {
    std::ofstream out(output.temp_path(), std::ios::binary);
    out.write(kCacheMagic, sizeof kCacheMagic);
    WriteVector(out, std::vector<char>(fingerprint.begin(), fingerprint.end()));
    std::string names;
    for (const std::string& name : subject_names_) names += name + "\n";
    WriteVector(out, std::vector<char>(names.begin(), names.end()));
    WriteVector(out, mean_[kAhead]);
    WriteVector(out, mean_[kLookDown]);
    for (const auto& mode : modes_) WriteVector(out, mode[kAhead]), WriteVector(out, mode[kLookDown]);
    WriteVector(out, stddev_);
    for (const auto& c : coefficients_) WriteVector(out, c);
    WriteVector(out, footprint_);
    if (!out) Fail(ExitCode::kOutput, "cannot write the texture cache {}", path.string());
  }
  output.Commit();
}

bool SkinTextureModel::TryLoad(const fs::path& path, const std::string& fingerprint, int num_modes, SkinTextureModel& model) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  char magic[sizeof kCacheMagic];
  in.read(magic, sizeof magic);
  if (!in || !std::equal(magic, magic + sizeof magic, kCacheMagic)) return false;
  std::vector<char> stored, names;
  if (!ReadVector(in, stored, 1024) || std::string(stored.begin(), stored.end()) != fingerprint) return false;
  if (!ReadVector(in, names, 4096)) return false;
  const uint64_t plane = static_cast<uint64_t>(kSize) * kSize * kChannels;
  if (!ReadVector(in, model.mean_[kAhead], plane) || !ReadVector(in, model.mean_[kLookDown], plane)) return false;
  model.modes_.resize(num_modes);
  for (auto& mode : model.modes_) {
    if (!ReadVector(in, mode[kAhead], plane) || !ReadVector(in, mode[kLookDown], plane)) return false;
  }
  if (!ReadVector(in, model.stddev_, 64) || static_cast<int>(model.stddev_.size()) != num_modes) return false;
  std::string list(names.begin(), names.end());
  for (std::size_t start = 0, end; (end = list.find('\n', start)) != std::string::npos; start = end + 1) {
    model.subject_names_.push_back(list.substr(start, end - start));
  }
  model.coefficients_.resize(model.subject_names_.size());
  for (auto& c : model.coefficients_) {
    if (!ReadVector(in, c, 64)) return false;
  }
  if (!ReadVector(in, model.footprint_, plane)) return false;
  return model.mean_[kAhead].size() == plane && model.footprint_.size() == plane / kChannels;
}

SkinTextureModel SkinTextureModel::LoadOrBuild(const fs::path& skin_dir, const fs::path& cache_dir, int num_modes) {
  std::vector<fs::path> inputs = SkinMaps(skin_dir);
  const std::size_t maps = inputs.size();
  for (std::size_t i = 0; i < maps; ++i) inputs.push_back(LookDownOf(inputs[i]));
  inputs.push_back(skin_dir / "face_uvs.png");
  const std::string fingerprint = Fingerprint(inputs, num_modes);
  const fs::path cache = cache_dir / ("skin_texture_pca_" + std::to_string(kSize) + "_" + std::to_string(num_modes) + ".bin");
  SkinTextureModel model;
  if (TryLoad(cache, fingerprint, num_modes, model)) return model;
  spdlog::info("building the skin texture model from {} scanned maps (once; cached in {})", maps, cache_dir.string());
  model = Build(skin_dir, num_modes);
  try {
    model.Save(cache, fingerprint);
  } catch (const Error& e) {
    spdlog::warn("cannot cache the texture model: {}", e.what());
  }
  return model;
}

}  // namespace gazedirector
