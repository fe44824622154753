#include "gazedirector/fit/appearance_gaze.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <utility>

#include <Eigen/Cholesky>
#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>

#include "gazedirector/io/atomic_output.h"
#include "gazedirector/io/json_format.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace fs = std::filesystem;
namespace {

// The band of the kGrid x kGrid crop that holds the eye and its lids.
constexpr int kFirstRow = 3, kLastRow = 10, kFirstColumn = 2, kLastColumn = 13;
constexpr int kBandRows = kLastRow - kFirstRow + 1, kBandColumns = kLastColumn - kFirstColumn + 1;
constexpr int kBandPixels = kBandRows * kBandColumns;
constexpr const char* kFormat = "gazedirector-appearance-gaze-7";
// The head yaw that the turned kernel counts as a turn of 1.
constexpr double kTurnScaleDeg = 30.0;

// Yaws are learned in the mirrored frame, where both eyes turn alike.
double MirroredYawSign(int eye) { return eye == kLeftEye ? -1.0 : 1.0; }

// 16-pixel blocks every 8 pixels, each of four 8-pixel cells, 9 orientations.
const cv::HOGDescriptor& Hog() {
  static const cv::HOGDescriptor hog(cv::Size(AppearanceGaze::kHogSize, AppearanceGaze::kHogSize), cv::Size(16, 16),
                                     cv::Size(8, 8), cv::Size(8, 8), 9);
  return hog;
}

// The crop in grey, the subject's left eye mirrored.
cv::Mat MirroredGrey(const cv::Mat& crop, int eye) {
  if (crop.empty()) Fail(ExitCode::kBadInput, "appearance gaze: empty crop");
  if (crop.depth() != CV_8U) Fail(ExitCode::kBadInput, "appearance gaze: a crop needs 8-bit pixels");
  cv::Mat grey;
  if (crop.channels() == 3) {
    cv::cvtColor(crop, grey, cv::COLOR_BGR2GRAY);
  } else if (crop.channels() == 1) {
    grey = crop.clone();
  } else {
    Fail(ExitCode::kBadInput, "appearance gaze: a crop needs 1 or 3 channels, not {}", crop.channels());
  }
  if (eye == kLeftEye) cv::flip(grey, grey, 1);
  return grey;
}

// The band's pixels, standardised.
Eigen::VectorXd BandPixels(const cv::Mat& grey) {
  cv::Mat small;
  cv::resize(grey, small, cv::Size(AppearanceGaze::kGrid, AppearanceGaze::kGrid), 0, 0, cv::INTER_AREA);
  cv::Mat band;
  small(cv::Rect(kFirstColumn, kFirstRow, kBandColumns, kBandRows)).convertTo(band, CV_64F);
  cv::Scalar mean, deviation;
  cv::meanStdDev(band, mean, deviation);
  Eigen::VectorXd pixels(kBandPixels);
  for (int y = 0; y < kBandRows; ++y) {
    for (int x = 0; x < kBandColumns; ++x) {
      pixels[y * kBandColumns + x] = (band.at<double>(y, x) - mean[0]) / (deviation[0] + 1e-6);
    }
  }
  return pixels;
}

Eigen::VectorXd Gradients(const cv::Mat& grey) {
  cv::Mat small;
  cv::resize(grey, small, cv::Size(AppearanceGaze::kHogSize, AppearanceGaze::kHogSize), 0, 0, cv::INTER_AREA);
  std::vector<float> histogram;
  Hog().compute(small, histogram);
  const Eigen::Index size = static_cast<Eigen::Index>(histogram.size());
  return Eigen::Map<const Eigen::VectorXf>(histogram.data(), size).cast<double>();
}

// The head's yaw in the mirrored frame over kTurnScaleDeg, as the turned
// kernel (of the camera and turned yaws) weighs it against each exemplar's.
double TurnOf(int eye, double head_yaw) { return MirroredYawSign(eye) * head_yaw / kTurnScaleDeg; }

// exp(-x² / 2w²): how frontal a head yaw x reads at width w.
double Gaussian(double x, double width) { return std::exp(-0.5 * std::pow(x / width, 2)); }
// In the kernel's units (the standardised features): how far apart the two
// eyes' sides are, and a head turn of kTurnScaleDeg.
constexpr double kSideWeight = 3.0, kTurnWeight = 10.0;

std::vector<double> ToVector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

Eigen::VectorXd ToEigen(const std::vector<double>& v) { return Eigen::Map<const Eigen::VectorXd>(v.data(), v.size()); }

// The exemplars as little-endian floats, row after row.
nlohmann::json::binary_t ToBytes(const Eigen::MatrixXf& exemplars) {
  const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = exemplars;
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(rows.data());
  return nlohmann::json::binary_t(std::vector<std::uint8_t>(bytes, bytes + rows.size() * sizeof(float)));
}

}  // namespace

int AppearanceGaze::NumBandFeatures() { return kBandPixels + 1; }

int AppearanceGaze::NumCropFeatures() {
  return kBandPixels + static_cast<int>(Hog().getDescriptorSize()) + 1;
}

Eigen::VectorXd AppearanceGaze::BandFeatures(const cv::Mat& crop, int eye) {
  Eigen::VectorXd features(NumBandFeatures());
  features << BandPixels(MirroredGrey(crop, eye)), MirroredYawSign(eye);
  return features;
}

Eigen::VectorXd AppearanceGaze::CropFeatures(const cv::Mat& crop, int eye) {
  const cv::Mat grey = MirroredGrey(crop, eye);
  Eigen::VectorXd features(NumCropFeatures());
  features << BandPixels(grey), Gradients(grey), MirroredYawSign(eye);
  return features;
}

double AppearanceGaze::ReadHeadYaw(const cv::Mat& crop, int eye) const {
  return HeadYawOf(SquaredDistances(CropFeatures(crop, eye), eye), eye);
}

AppearanceReading AppearanceGaze::Read(const cv::Mat& crop, int eye, double head_yaw) const {
  return ReadAt(SquaredDistances(CropFeatures(crop, eye), eye), eye, head_yaw, HeadYaw::kGiven);
}

AppearanceReading AppearanceGaze::ReadGivenHeadReading(const cv::Mat& crop, int eye, double read_head_yaw) const {
  return ReadAt(SquaredDistances(CropFeatures(crop, eye), eye), eye, read_head_yaw, HeadYaw::kRead);
}

AppearanceReading AppearanceGaze::Read(const cv::Mat& crop, int eye) const {
  const Eigen::VectorXd squared_distances = SquaredDistances(CropFeatures(crop, eye), eye);
  return ReadAt(squared_distances, eye, HeadYawOf(squared_distances, eye), HeadYaw::kRead);
}

Eigen::VectorXd AppearanceGaze::SquaredDistances(const Eigen::VectorXd& features, int eye) const {
  const Eigen::Index n = feature_mean_.size();
  Eigen::VectorXf standardised(n + 1);
  standardised.head(n) = ((features.head(n) - feature_mean_).array() / feature_scale_.array()).cast<float>();
  standardised[n] = static_cast<float>(kSideWeight * MirroredYawSign(eye));
  return (exemplars_.rowwise() - standardised.transpose()).rowwise().squaredNorm().cast<double>();
}

Eigen::VectorXd AppearanceGaze::Kernel(const Eigen::VectorXd& squared_distances) const {
  return (-squared_distances.array() / kernel_width_).exp().matrix();
}

Eigen::VectorXd AppearanceGaze::TurnedKernel(const Eigen::VectorXd& squared_distances, int eye,
                                             double head_yaw) const {
  const Eigen::ArrayXd turns = kTurnWeight * (exemplar_turns_.array() - TurnOf(eye, head_yaw));
  return Kernel(squared_distances + turns.square().matrix());
}

double AppearanceGaze::Evaluate(const Regression& regression, const Eigen::VectorXd& kernel) const {
  return regression.offset + regression.weights.dot(kernel);
}

double AppearanceGaze::HeadYawOf(const Eigen::VectorXd& squared_distances, int eye) const {
  return MirroredYawSign(eye) * Evaluate(head_yaw_, Kernel(squared_distances));
}

AppearanceReading AppearanceGaze::ReadAt(const Eigen::VectorXd& squared_distances, int eye, double head_yaw,
                                         HeadYaw head_yaw_is) const {
  const double frontal = Gaussian(head_yaw, kFrontalWidthDeg);
  const double frontal_share = Gaussian(head_yaw, kFrontalYawWidthDeg);
  const Eigen::VectorXd kernel = Kernel(squared_distances);
  AppearanceReading reading;
  reading.pitch = Evaluate(pitch_, kernel);
  double turned;
  if (head_yaw_is == HeadYaw::kGiven) {
    const double camera_yaw =
        MirroredYawSign(eye) * Evaluate(camera_yaw_, TurnedKernel(squared_distances, eye, head_yaw));
    turned = EyeRegionModel::CameraGazeInHead(reading.pitch, camera_yaw, head_yaw).y();
  } else {
    const double turn = head_yaw / head_yaw_slope_;
    turned = MirroredYawSign(eye) * Evaluate(turned_yaw_, TurnedKernel(squared_distances, eye, turn));
  }
  reading.yaw = frontal_share * MirroredYawSign(eye) * Evaluate(frontal_yaw_, kernel) + (1 - frontal_share) * turned;
  reading.head_yaw = head_yaw;
  reading.frontal = frontal;
  return reading;
}

void AppearanceGaze::Save(const fs::path& path) const {
  auto regression = [](const Regression& r) {
    return nlohmann::json{{"offset", r.offset}, {"weights", ToVector(r.weights)}};
  };
  const nlohmann::json json = {
      {"format", kFormat},
      {"grid", kGrid},
      {"band", {kFirstRow, kLastRow, kFirstColumn, kLastColumn}},
      {"hog_size", kHogSize},
      {"frontal_width_deg", kFrontalWidthDeg},
      {"frontal_yaw_width_deg", kFrontalYawWidthDeg},
      {"side_weight", kSideWeight},
      {"turn_weight", kTurnWeight},
      {"ridge", ridge_},
      {"kernel_width", kernel_width_},
      {"head_yaw_slope", head_yaw_slope_},
      {"samples",
       {{"pitch", samples_.pitch},
        {"frontal_yaw", samples_.frontal_yaw},
        {"camera_yaw", samples_.camera_yaw},
        {"turned_yaw", samples_.turned_yaw},
        {"head_yaw", samples_.head_yaw}}},
      {"subjects", subjects_},
      {"feature_mean", ToVector(feature_mean_)},
      {"feature_scale", ToVector(feature_scale_)},
      {"exemplar_count", exemplars_.rows()},
      {"exemplars", ToBytes(exemplars_)},
      {"exemplar_turns", ToVector(exemplar_turns_)},
      {"regressions",
       {{"pitch", regression(pitch_)},
        {"frontal_mirrored_yaw", regression(frontal_yaw_)},
        {"mirrored_camera_yaw", regression(camera_yaw_)},
        {"mirrored_turned_yaw", regression(turned_yaw_)},
        {"mirrored_head_yaw", regression(head_yaw_)}}}};
  const std::vector<std::uint8_t> bytes = nlohmann::json::to_cbor(json);
  WriteTextFile(path, std::string(bytes.begin(), bytes.end()));
}

AppearanceGaze AppearanceGaze::Load(const fs::path& path) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream) {
    Fail(ExitCode::kAssets, "{}: cannot read the appearance gaze model (the build trains it: cmake --build --preset release)",
         path.string());
  }
  AppearanceGaze model;
  try {
    const nlohmann::json json = nlohmann::json::from_cbor(stream);
    if (!json.is_object() || json.value("format", "") != kFormat || json.at("grid") != kGrid ||
        json.at("band") != nlohmann::json({kFirstRow, kLastRow, kFirstColumn, kLastColumn}) ||
        json.at("hog_size") != kHogSize || json.at("frontal_width_deg") != kFrontalWidthDeg ||
        json.at("frontal_yaw_width_deg") != kFrontalYawWidthDeg ||
        json.at("side_weight") != kSideWeight || json.at("turn_weight") != kTurnWeight) {
      Fail(ExitCode::kAssets, "{}: not a {} model", path.string(), kFormat);
    }
    const int features = NumCropFeatures() - 1;
    const Eigen::Index count = json.at("exemplar_count").get<Eigen::Index>();
    const std::vector<std::uint8_t>& bytes = json.at("exemplars").get_binary();
    if (count <= 0 || bytes.size() != static_cast<size_t>(count) * (features + 1) * sizeof(float)) {
      Fail(ExitCode::kAssets, "{}: {} bytes of exemplars where {} of {} features were expected", path.string(),
           bytes.size(), count, features + 1);
    }
    model.exemplars_ = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        reinterpret_cast<const float*>(bytes.data()), count, features + 1);
    auto load = [&](const nlohmann::json& values, Eigen::Index size, const char* key) {
      const Eigen::VectorXd loaded = ToEigen(values.get<std::vector<double>>());
      if (loaded.size() != size) {
        Fail(ExitCode::kAssets, "{}: {} {} values where {} were expected", path.string(), loaded.size(), key, size);
      }
      if (!loaded.allFinite()) Fail(ExitCode::kAssets, "{}: {} values are not finite", path.string(), key);
      return loaded;
    };
    model.feature_mean_ = load(json.at("feature_mean"), features, "feature_mean");
    model.feature_scale_ = load(json.at("feature_scale"), features, "feature_scale");
    model.exemplar_turns_ = load(json.at("exemplar_turns"), count, "exemplar_turns");
    const nlohmann::json& regressions = json.at("regressions");
    auto regression = [&](const char* key) {
      const nlohmann::json& r = regressions.at(key);
      return Regression{load(r.at("weights"), count, key), r.at("offset").get<double>()};
    };
    model.pitch_ = regression("pitch");
    model.frontal_yaw_ = regression("frontal_mirrored_yaw");
    model.camera_yaw_ = regression("mirrored_camera_yaw");
    model.turned_yaw_ = regression("mirrored_turned_yaw");
    model.head_yaw_ = regression("mirrored_head_yaw");
    model.subjects_ = json.at("subjects").get<std::vector<std::string>>();
    model.ridge_ = json.at("ridge").get<double>();
    model.kernel_width_ = json.at("kernel_width").get<double>();
    model.head_yaw_slope_ = json.at("head_yaw_slope").get<double>();
    if (!(model.kernel_width_ > 0) || !(model.feature_scale_.array() > 0).all()) {
      Fail(ExitCode::kAssets, "{}: its kernel width or feature scales are not positive", path.string());
    }
    if (!(model.head_yaw_slope_ > 0.1 && model.head_yaw_slope_ < 10)) {
      Fail(ExitCode::kAssets, "{}: head_yaw_slope {} is not usable", path.string(), model.head_yaw_slope_);
    }
    const nlohmann::json& samples = json.at("samples");
    model.samples_ = {samples.at("pitch").get<int>(), samples.at("frontal_yaw").get<int>(),
                      samples.at("camera_yaw").get<int>(), samples.at("turned_yaw").get<int>(),
                      samples.at("head_yaw").get<int>()};
  } catch (const nlohmann::json::exception& e) {
    Fail(ExitCode::kAssets, "{}: not a valid appearance gaze model ({})", path.string(), JsonErrorText(e));
  }
  return model;
}

AppearanceGazeTrainer::AppearanceGazeTrainer(double ridge) : ridge_(ridge) {}

void AppearanceGazeTrainer::Add(const std::string& subject, const cv::Mat& crop, int eye,
                                const AppearanceLabel& label) {
  const double sign = MirroredYawSign(eye);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Sample sample;
  sample.features = AppearanceGaze::CropFeatures(crop, eye);
  sample.pitch = label.pitch;
  sample.frontal_yaw = label.head_yaw == 0 ? sign * label.yaw : nan;
  // Both learned against the head's turn, so they need both labels. Relative
  // to the camera: the gaze relative to the head turned back by the head's yaw.
  const double pitch = std::isnan(label.pitch) ? 0.0 : label.pitch;
  const bool turn_known = !std::isnan(label.yaw) && !std::isnan(label.head_yaw);
  sample.camera_yaw = turn_known ? sign * EyeRegionModel::CameraGazeInHead(pitch, label.yaw, -label.head_yaw).y() : nan;
  sample.turned_yaw = turn_known ? sign * label.yaw : nan;
  sample.head_yaw = sign * label.head_yaw;
  by_subject_[subject].push_back(std::move(sample));
}

namespace {

// Twice the median squared distance between (at most about 800) exemplars:
// the kernel's width, so that a typical pair of crops weighs exp(-1/2).
double KernelWidth(const Eigen::MatrixXd& squared_distances) {
  const Eigen::Index n = squared_distances.rows();
  const Eigen::Index step = std::max<Eigen::Index>(1, n / 800);
  std::vector<double> pairs;
  for (Eigen::Index i = 0; i < n; i += step) {
    for (Eigen::Index j = 0; j < i; j += step) pairs.push_back(squared_distances(i, j));
  }
  if (pairs.empty()) return 1.0;
  std::nth_element(pairs.begin(), pairs.begin() + pairs.size() / 2, pairs.end());
  return std::max(2.0 * pairs[pairs.size() / 2], 1e-9);
}

}  // namespace

// Each training subject read by the head-yaw regression trained without them
// (the offset held), the least-squares slope of reading on label through 0.
// For a kernel ridge regression with A = K + ridge I and weights A⁻¹y, the
// subject's rows g read y_g - [(A⁻¹)_gg]⁻¹ (A⁻¹y)_g without their own crops,
// so one factor serves every subject: (A⁻¹)_gg is XᵀX for the columns g of
// L⁻¹, and since the rows of a subject are contiguous, those columns are
// zero above the subject's first row.
double AppearanceGazeTrainer::HeadYawSlope(const Eigen::LLT<Eigen::MatrixXd>& factor,
                                           const std::vector<Eigen::Index>& rows,
                                           const std::vector<const Sample*>& samples,
                                           const std::vector<int>& subject_of,
                                           const AppearanceGaze::Regression& head) {
  const Eigen::Index m = static_cast<Eigen::Index>(rows.size());
  const Eigen::MatrixXd& lower = factor.matrixLLT();  // L in its lower triangle
  double reading_times_label = 0, label_squares = 0;
  for (Eigen::Index first = 0; first < m;) {
    Eigen::Index end = first;
    while (end < m && subject_of[rows[end]] == subject_of[rows[first]]) ++end;
    const Eigen::Index size = end - first;
    if (size == m) break;  // one subject: nothing to leave out
    Eigen::MatrixXd columns = Eigen::MatrixXd::Identity(m - first, size);
    lower.bottomRightCorner(m - first, m - first).triangularView<Eigen::Lower>().solveInPlace(columns);
    Eigen::VectorXd weights(size), labels(size);
    for (Eigen::Index a = 0; a < size; ++a) {
      weights[a] = head.weights[rows[first + a]];
      labels[a] = samples[rows[first + a]]->head_yaw;
    }
    const Eigen::VectorXd residuals = (columns.transpose() * columns).llt().solve(weights);
    const Eigen::VectorXd readings = labels - residuals;
    reading_times_label += readings.dot(labels);
    label_squares += labels.squaredNorm();
    first = end;
  }
  // One subject, or heads that all face the camera: nothing to learn it from.
  if (label_squares <= 0 || reading_times_label <= 0) return 1.0;
  return reading_times_label / label_squares;
}

Eigen::VectorXd AppearanceGazeTrainer::TurnOverPersonWeights(const Eigen::MatrixXd& standardised,
                                                             const std::vector<double>& turns,
                                                             const std::vector<int>& subject_of) {
  const Eigen::Index features = standardised.cols();
  if (static_cast<Eigen::Index>(turns.size()) != standardised.rows() ||
      static_cast<Eigen::Index>(subject_of.size()) != standardised.rows()) {
    Fail(ExitCode::kInternal, "appearance gaze: {} crops with {} turns and {} subjects", standardised.rows(),
         turns.size(), subject_of.size());
  }
  struct Mean {
    Eigen::VectorXd sum;
    int count = 0;
    void Add(const Eigen::VectorXd& v) {
      if (count++ == 0) {
        sum = v;
      } else {
        sum += v;
      }
    }
    Eigen::VectorXd Value() const { return sum / count; }
  };
  std::map<long, Mean> by_turn;
  std::map<std::pair<long, int>, Mean> by_turn_and_subject;
  for (Eigen::Index i = 0; i < standardised.rows(); ++i) {
    if (std::isnan(turns[i])) continue;
    const long turn = std::lround(turns[i]);
    by_turn[turn].Add(standardised.row(i).transpose());
    by_turn_and_subject[{turn, subject_of[i]}].Add(standardised.row(i).transpose());
  }
  if (by_turn.size() < 2 || by_turn_and_subject.size() <= by_turn.size()) return Eigen::VectorXd::Ones(features);
  auto variance = [features](const std::vector<Eigen::VectorXd>& values) {
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(features), squares = Eigen::VectorXd::Zero(features);
    for (const Eigen::VectorXd& v : values) mean += v;
    mean /= static_cast<double>(values.size());
    for (const Eigen::VectorXd& v : values) squares += (v - mean).cwiseAbs2();
    return Eigen::VectorXd(squares / static_cast<double>(values.size()));
  };
  std::map<long, Eigen::VectorXd> turn_mean;
  std::vector<Eigen::VectorXd> turn_means, person_offsets;
  for (const auto& [turn, mean] : by_turn) turn_means.push_back(turn_mean[turn] = mean.Value());
  for (const auto& [key, mean] : by_turn_and_subject) person_offsets.push_back(mean.Value() - turn_mean.at(key.first));
  const Eigen::ArrayXd person = variance(person_offsets).array() + 1e-6;
  const Eigen::VectorXd weights = (variance(turn_means).array() / person).sqrt().max(1e-3).matrix();
  return weights / std::sqrt(weights.squaredNorm() / static_cast<double>(features));
}

namespace {

// The squared Euclidean distances between the rows of `points`.
Eigen::MatrixXd SquaredDistancesBetween(const Eigen::MatrixXd& points) {
  const Eigen::VectorXd norms = points.rowwise().squaredNorm();
  Eigen::MatrixXd squared = -2.0 * points * points.transpose();
  squared.colwise() += norms;
  squared.rowwise() += norms.transpose();
  return squared.cwiseMax(0.0);
}

// Kernel ridge regressions over one set of exemplars: a Gaussian kernel in
// their squared distances, with the head turns' term for the regressions that
// read a turned eye (the camera and turned yaws), the ridge on its diagonal.
class KernelRidge {
 public:
  struct Solved {
    Eigen::VectorXd weights;  // one per exemplar; 0 for those without a label
    double offset = 0;
    int samples = 0;
    std::shared_ptr<const Eigen::LLT<Eigen::MatrixXd>> factor;
    std::vector<Eigen::Index> rows;  // the exemplars it learned from
  };

  KernelRidge(const Eigen::MatrixXd& squared_distances, const Eigen::VectorXd& turns, double width, double ridge)
      : squared_(squared_distances), turns_(turns), width_(width), ridge_(ridge) {}

  // The regression of `labels` (one per exemplar, NaN: unknown) on the
  // exemplars whose label is known. `same`: a regression on the same kernel,
  // whose factor serves when it learned from the same exemplars.
  Solved Solve(const Eigen::VectorXd& labels, bool turned, const char* name, const Solved* same = nullptr) const {
    Solved solved;
    for (Eigen::Index i = 0; i < labels.size(); ++i) {
      if (!std::isnan(labels[i])) solved.rows.push_back(i);
    }
    const Eigen::Index m = static_cast<Eigen::Index>(solved.rows.size());
    solved.samples = static_cast<int>(m);
    if (m == 0) Fail(ExitCode::kBadInput, "appearance gaze: no training crops labelled with {}", name);
    Eigen::VectorXd known(m);
    for (Eigen::Index a = 0; a < m; ++a) known[a] = labels[solved.rows[a]];
    solved.offset = known.mean();
    if (same != nullptr && same->rows == solved.rows) {
      solved.factor = same->factor;
    } else {
      solved.factor = std::make_shared<const Eigen::LLT<Eigen::MatrixXd>>(Matrix(solved.rows, turned));
    }
    const Eigen::VectorXd weights = solved.factor->solve((known.array() - solved.offset).matrix());
    solved.weights.setZero(labels.size());
    for (Eigen::Index a = 0; a < m; ++a) solved.weights[solved.rows[a]] = weights[a];
    return solved;
  }

 private:
  Eigen::MatrixXd Matrix(const std::vector<Eigen::Index>& rows, bool turned) const {
    const Eigen::Index m = static_cast<Eigen::Index>(rows.size());
    Eigen::MatrixXd kernel(m, m);
    for (Eigen::Index b = 0; b < m; ++b) {
      for (Eigen::Index a = 0; a < m; ++a) {
        const Eigen::Index i = rows[a], j = rows[b];
        double distance = squared_(i, j);
        if (turned) distance += std::pow(kTurnWeight * (turns_[i] - turns_[j]), 2);
        kernel(a, b) = std::exp(-distance / width_);
      }
    }
    kernel.diagonal().array() += ridge_;
    return kernel;
  }

  const Eigen::MatrixXd& squared_;
  const Eigen::VectorXd& turns_;
  double width_, ridge_;
};

}  // namespace

void AppearanceGazeTrainer::SetExemplars(const std::vector<const Sample*>& samples, const std::vector<int>& subject_of,
                                         AppearanceGaze& model) {
  const Eigen::Index n = static_cast<Eigen::Index>(samples.size());
  // The features standardised over the training crops, the eye's side weighed.
  const Eigen::Index features = AppearanceGaze::NumCropFeatures() - 1;
  Eigen::MatrixXd exemplars(n, features + 1);
  for (Eigen::Index i = 0; i < n; ++i) exemplars.row(i) = samples[i]->features.transpose();
  model.feature_mean_ = exemplars.leftCols(features).colwise().mean().transpose();
  exemplars.leftCols(features).rowwise() -= model.feature_mean_.transpose();
  model.feature_scale_ = (exemplars.leftCols(features).colwise().squaredNorm() / n).cwiseSqrt().transpose();
  for (double& scale : model.feature_scale_) scale = scale > 1e-9 ? scale : 1.0;
  exemplars.leftCols(features) = exemplars.leftCols(features) * model.feature_scale_.cwiseInverse().asDiagonal();
  // In most features people differ more than one person's turns of the head
  // do; weighed by how much more they tell the turn, the kernel looks past
  // who the person is. People left out, every 5th Columbia photo: the head
  // read from a photo's crops errs by 0.1-0.4 degrees less at every head
  // pose, the fitted gaze's yaw 3.75 degrees instead of 3.80 (session 52).
  std::vector<double> turns(n);
  for (Eigen::Index i = 0; i < n; ++i) turns[i] = samples[i]->head_yaw;
  const Eigen::VectorXd emphasis = TurnOverPersonWeights(exemplars.leftCols(features), turns, subject_of);
  exemplars.leftCols(features) = exemplars.leftCols(features) * emphasis.asDiagonal();
  model.feature_scale_ = model.feature_scale_.cwiseQuotient(emphasis);
  exemplars.col(features) *= kSideWeight;
  model.exemplars_ = exemplars.cast<float>();
  model.exemplar_turns_.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double head_yaw = samples[i]->head_yaw;
    model.exemplar_turns_[i] = std::isnan(head_yaw) ? 0.0 : head_yaw / kTurnScaleDeg;  // already mirrored
  }
}

AppearanceGaze AppearanceGazeTrainer::Solve(const std::string& left_out) const {
  std::vector<const Sample*> samples;
  std::vector<int> subject_of;  // an index per training subject, in the samples' order
  AppearanceGaze model;
  for (const auto& [subject, these] : by_subject_) {
    if (subject == left_out) continue;
    for (const Sample& sample : these) {
      samples.push_back(&sample);
      subject_of.push_back(static_cast<int>(model.subjects_.size()));
    }
    model.subjects_.push_back(subject);
  }
  if (samples.empty()) Fail(ExitCode::kBadInput, "appearance gaze: no training crops labelled with pitch");
  SetExemplars(samples, subject_of, model);
  // Distances as the reading computes them, from the float exemplars.
  const Eigen::MatrixXd squared = SquaredDistancesBetween(model.exemplars_.cast<double>());
  model.kernel_width_ = KernelWidth(squared);
  const KernelRidge kernel(squared, model.exemplar_turns_, model.kernel_width_, ridge_);

  auto labels = [&](double Sample::*label) {
    Eigen::VectorXd values(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) values[i] = samples[i]->*label;
    return values;
  };
  const KernelRidge::Solved pitch = kernel.Solve(labels(&Sample::pitch), false, "pitch");
  const KernelRidge::Solved frontal = kernel.Solve(labels(&Sample::frontal_yaw), false, "yaw with the head facing the camera");
  const KernelRidge::Solved camera = kernel.Solve(labels(&Sample::camera_yaw), true, "yaw");
  const KernelRidge::Solved turned = kernel.Solve(labels(&Sample::turned_yaw), true, "yaw", &camera);
  const KernelRidge::Solved head = kernel.Solve(labels(&Sample::head_yaw), false, "head yaw", &pitch);
  model.pitch_ = {pitch.weights, pitch.offset};
  model.frontal_yaw_ = {frontal.weights, frontal.offset};
  model.camera_yaw_ = {camera.weights, camera.offset};
  model.turned_yaw_ = {turned.weights, turned.offset};
  model.head_yaw_ = {head.weights, head.offset};
  model.samples_.pitch = pitch.samples;
  model.samples_.frontal_yaw = frontal.samples;
  model.samples_.camera_yaw = camera.samples;
  model.samples_.turned_yaw = turned.samples;
  model.samples_.head_yaw = head.samples;
  model.head_yaw_slope_ = HeadYawSlope(*head.factor, head.rows, samples, subject_of, model.head_yaw_);
  model.ridge_ = ridge_;
  return model;
}

std::vector<std::string> AppearanceGazeTrainer::subjects() const {
  std::vector<std::string> names;
  for (const auto& [subject, these] : by_subject_) names.push_back(subject);
  return names;
}

}  // namespace gazedirector
