#include "gazedirector/fit/appearance_gaze.h"

#include <cmath>
#include <fstream>
#include <limits>

#include <Eigen/Cholesky>
#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>

#include "gazedirector/io/atomic_output.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace fs = std::filesystem;
namespace {

// The band of the kGrid x kGrid crop that holds the eye and its lids.
constexpr int kFirstRow = 3, kLastRow = 10, kFirstColumn = 2, kLastColumn = 13;
constexpr int kBandRows = kLastRow - kFirstRow + 1, kBandColumns = kLastColumn - kFirstColumn + 1;
constexpr int kBandPixels = kBandRows * kBandColumns;
constexpr const char* kFormat = "gazedirector-appearance-gaze-6";
// The head yaw that scales the turned features: 1 at a 30-degree turn.
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

Eigen::VectorXd CropRow(const cv::Mat& grey, int eye) {
  Eigen::VectorXd row(AppearanceGaze::NumCropFeatures() + 1);
  row << BandPixels(grey), Gradients(grey), MirroredYawSign(eye), 1.0;
  return row;
}

// The whole crop's features, then the same scaled by the head's yaw in the
// mirrored frame (t, 1 at kTurnScaleDeg), then t and t², the eye's side and the
// intercept: the last four are not penalised (kTurnedOffsets).
Eigen::VectorXd TurnedRow(const Eigen::VectorXd& crop, int eye, double head_yaw) {
  const Eigen::Index n = crop.size() - 2;
  const double t = MirroredYawSign(eye) * head_yaw / kTurnScaleDeg;
  Eigen::VectorXd row(2 * n + 4);
  row << crop.head(n), t * crop.head(n), t, t * t, crop.tail(2);
  return row;
}
constexpr int kOffsets = 2, kTurnedOffsets = 4;

std::vector<double> ToVector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

}  // namespace

int AppearanceGaze::NumBandFeatures() { return kBandPixels + 1; }

int AppearanceGaze::NumCropFeatures() {
  return kBandPixels + static_cast<int>(Hog().getDescriptorSize()) + 1;
}

int AppearanceGaze::NumTurnedFeatures() { return 2 * (NumCropFeatures() - 1) + 3; }

Eigen::VectorXd AppearanceGaze::BandFeatures(const cv::Mat& crop, int eye) {
  Eigen::VectorXd features(NumBandFeatures());
  features << BandPixels(MirroredGrey(crop, eye)), MirroredYawSign(eye);
  return features;
}

Eigen::VectorXd AppearanceGaze::CropFeatures(const cv::Mat& crop, int eye) {
  return CropRow(MirroredGrey(crop, eye), eye).head(NumCropFeatures());
}

double AppearanceGaze::ReadHeadYaw(const cv::Mat& crop, int eye) const {
  return HeadYawOf(CropRow(MirroredGrey(crop, eye), eye), eye);
}

AppearanceReading AppearanceGaze::Read(const cv::Mat& crop, int eye, double head_yaw) const {
  return ReadTurnedBy(CropRow(MirroredGrey(crop, eye), eye), eye, head_yaw, head_yaw);
}

AppearanceReading AppearanceGaze::ReadGivenHeadReading(const cv::Mat& crop, int eye, double read_head_yaw) const {
  return ReadTurnedBy(CropRow(MirroredGrey(crop, eye), eye), eye, read_head_yaw, read_head_yaw / head_yaw_slope_);
}

AppearanceReading AppearanceGaze::Read(const cv::Mat& crop, int eye) const {
  const Eigen::VectorXd row = CropRow(MirroredGrey(crop, eye), eye);
  const double read_head_yaw = HeadYawOf(row, eye);
  return ReadTurnedBy(row, eye, read_head_yaw, read_head_yaw / head_yaw_slope_);
}

double AppearanceGaze::HeadYawOf(const Eigen::VectorXd& row, int eye) const {
  return MirroredYawSign(eye) * head_yaw_.dot(row);
}

AppearanceReading AppearanceGaze::ReadTurnedBy(const Eigen::VectorXd& row, int eye, double head_yaw,
                                               double turn) const {
  const double frontal = std::exp(-0.5 * std::pow(head_yaw / kFrontalWidthDeg, 2));
  AppearanceReading reading;
  reading.pitch = pitch_.dot(row);
  const double camera_yaw = MirroredYawSign(eye) * camera_yaw_.dot(TurnedRow(row, eye, head_yaw));
  const double turned = EyeRegionModel::CameraGazeInHead(reading.pitch, camera_yaw, turn).y();
  reading.yaw = frontal * MirroredYawSign(eye) * frontal_yaw_.dot(row) + (1 - frontal) * turned;
  reading.head_yaw = head_yaw;
  reading.frontal = frontal;
  return reading;
}

nlohmann::json AppearanceGaze::ToJson() const {
  return {{"format", kFormat},
          {"grid", kGrid},
          {"band", {kFirstRow, kLastRow, kFirstColumn, kLastColumn}},
          {"hog_size", kHogSize},
          {"frontal_width_deg", kFrontalWidthDeg},
          {"ridge", ridge_},
          {"head_yaw_slope", head_yaw_slope_},
          {"samples",
           {{"pitch", samples_.pitch},
            {"frontal_yaw", samples_.frontal_yaw},
            {"camera_yaw", samples_.camera_yaw},
            {"head_yaw", samples_.head_yaw}}},
          {"subjects", subjects_},
          {"weights",
           {{"pitch", ToVector(pitch_)},
            {"frontal_mirrored_yaw", ToVector(frontal_yaw_)},
            {"mirrored_camera_yaw", ToVector(camera_yaw_)},
            {"mirrored_head_yaw", ToVector(head_yaw_)}}}};
}

AppearanceGaze AppearanceGaze::Load(const fs::path& path) {
  std::ifstream stream(path);
  if (!stream) {
    Fail(ExitCode::kAssets, "{}: cannot read the appearance gaze model (the repository's models/ folder holds it)",
         path.string());
  }
  AppearanceGaze model;
  try {
    const nlohmann::json json = nlohmann::json::parse(stream);
    if (json.at("format") != kFormat || json.at("grid") != kGrid ||
        json.at("band") != nlohmann::json({kFirstRow, kLastRow, kFirstColumn, kLastColumn}) ||
        json.at("hog_size") != kHogSize || json.at("frontal_width_deg") != kFrontalWidthDeg) {
      Fail(ExitCode::kAssets, "{}: not a {} model", path.string(), kFormat);
    }
    const nlohmann::json& weights = json.at("weights");
    auto load = [&](const char* key, int features) {
      const std::vector<double> values = weights.at(key).get<std::vector<double>>();
      if (static_cast<int>(values.size()) != features + 1) {
        Fail(ExitCode::kAssets, "{}: {} {} weights where {} were expected", path.string(), values.size(), key,
             features + 1);
      }
      const Eigen::VectorXd loaded = Eigen::Map<const Eigen::VectorXd>(values.data(), features + 1);
      if (!loaded.allFinite()) Fail(ExitCode::kAssets, "{}: {} weights are not finite", path.string(), key);
      return loaded;
    };
    model.pitch_ = load("pitch", NumCropFeatures());
    model.frontal_yaw_ = load("frontal_mirrored_yaw", NumCropFeatures());
    model.camera_yaw_ = load("mirrored_camera_yaw", NumTurnedFeatures());
    model.head_yaw_ = load("mirrored_head_yaw", NumCropFeatures());
    model.subjects_ = json.at("subjects").get<std::vector<std::string>>();
    model.ridge_ = json.at("ridge").get<double>();
    model.head_yaw_slope_ = json.at("head_yaw_slope").get<double>();
    if (!(model.head_yaw_slope_ > 0.1 && model.head_yaw_slope_ < 10)) {
      Fail(ExitCode::kAssets, "{}: head_yaw_slope {} is not usable", path.string(), model.head_yaw_slope_);
    }
    const nlohmann::json& samples = json.at("samples");
    model.samples_ = {samples.at("pitch").get<int>(), samples.at("frontal_yaw").get<int>(),
                      samples.at("camera_yaw").get<int>(), samples.at("head_yaw").get<int>()};
  } catch (const nlohmann::json::exception& e) {
    Fail(ExitCode::kAssets, "{}: not a valid appearance gaze model ({})", path.string(), e.what());
  }
  return model;
}

void AppearanceGaze::Save(const fs::path& path) const { WriteTextFile(path, ToJson().dump(1) + "\n"); }

AppearanceGazeTrainer::AppearanceGazeTrainer(double ridge) : ridge_(ridge) {}

void AppearanceGazeTrainer::Sums::Add(const Eigen::VectorXd& row, double label) {
  if (std::isnan(label)) return;
  if (samples == 0) {
    normal.setZero(row.size(), row.size());
    rhs.setZero(row.size());
  }
  normal.selfadjointView<Eigen::Lower>().rankUpdate(row);
  rhs += label * row;
  label_squares += label * label;
  ++samples;
}

void AppearanceGazeTrainer::Add(const std::string& subject, const cv::Mat& crop, int eye,
                                const AppearanceLabel& label) {
  const Eigen::VectorXd whole = CropRow(MirroredGrey(crop, eye), eye);
  const double sign = MirroredYawSign(eye);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  SubjectSums& sums = by_subject_[subject];
  sums.pitch.Add(whole, label.pitch);
  sums.frontal_yaw.Add(whole, label.head_yaw == 0 ? sign * label.yaw : nan);
  // Relative to the camera: the gaze relative to the head turned back by the head's yaw.
  const double pitch = std::isnan(label.pitch) ? 0.0 : label.pitch;
  const double camera_yaw = std::isnan(label.yaw) || std::isnan(label.head_yaw)
                                ? nan
                                : EyeRegionModel::CameraGazeInHead(pitch, label.yaw, -label.head_yaw).y();
  sums.camera_yaw.Add(TurnedRow(whole, eye, label.head_yaw), sign * camera_yaw);
  sums.head_yaw.Add(whole, sign * label.head_yaw);
}

AppearanceGazeTrainer::Sums AppearanceGazeTrainer::Total(const std::string& left_out,
                                                         Sums SubjectSums::*angle) const {
  Sums total;
  for (const auto& [subject, sums] : by_subject_) {
    const Sums& these = sums.*angle;
    if (subject == left_out || these.samples == 0) continue;
    if (total.samples == 0) {
      total = these;
    } else {
      total.normal += these.normal;
      total.rhs += these.rhs;
      total.label_squares += these.label_squares;
      total.samples += these.samples;
    }
  }
  return total;
}

Eigen::VectorXd AppearanceGazeTrainer::SolveRidge(Eigen::MatrixXd normal, const Eigen::VectorXd& rhs,
                                                  int offsets) const {
  // The last `offsets` features (the intercept, the eye's side and, turned,
  // t and t²) are not penalised: they carry offsets.
  normal.diagonal().head(normal.rows() - offsets).array() += ridge_;
  return normal.selfadjointView<Eigen::Lower>().ldlt().solve(rhs);
}

Eigen::VectorXd AppearanceGazeTrainer::SolveOne(const std::string& left_out, Sums SubjectSums::*angle, int offsets,
                                                const char* name, int& samples) const {
  const Sums total = Total(left_out, angle);
  samples = total.samples;
  if (samples == 0) Fail(ExitCode::kBadInput, "appearance gaze: no training crops labelled with {}", name);
  return SolveRidge(total.normal, total.rhs, offsets);
}

double AppearanceGazeTrainer::HeadYawSlope(const std::string& left_out) const {
  // Each training subject read by a regression trained without them and
  // without `left_out`: the sums of everyone but `left_out`, less the
  // subject's own. The sum over the subject's crops of reading times label
  // is the weights times the subject's Xᵀy, so no crop is kept.
  const Sums rest = Total(left_out, &SubjectSums::head_yaw);
  double reading_times_label = 0, label_squares = 0;
  for (const auto& [subject, sums] : by_subject_) {
    const Sums& these = sums.head_yaw;
    if (subject == left_out || these.samples == 0 || these.samples == rest.samples) continue;
    const Eigen::VectorXd weights = SolveRidge(rest.normal - these.normal, rest.rhs - these.rhs, kOffsets);
    reading_times_label += weights.dot(these.rhs);
    label_squares += these.label_squares;
  }
  // One subject, or heads that all face the camera: nothing to learn it from.
  if (label_squares <= 0 || reading_times_label <= 0) return 1.0;
  return reading_times_label / label_squares;
}

AppearanceGaze AppearanceGazeTrainer::Solve(const std::string& left_out) const {
  AppearanceGaze model;
  model.pitch_ = SolveOne(left_out, &SubjectSums::pitch, kOffsets, "pitch", model.samples_.pitch);
  model.frontal_yaw_ = SolveOne(left_out, &SubjectSums::frontal_yaw, kOffsets, "yaw with the head facing the camera",
                                model.samples_.frontal_yaw);
  model.camera_yaw_ = SolveOne(left_out, &SubjectSums::camera_yaw, kTurnedOffsets, "yaw", model.samples_.camera_yaw);
  model.head_yaw_ = SolveOne(left_out, &SubjectSums::head_yaw, kOffsets, "head yaw", model.samples_.head_yaw);
  model.head_yaw_slope_ = HeadYawSlope(left_out);
  for (const auto& [subject, sums] : by_subject_) {
    if (subject != left_out) model.subjects_.push_back(subject);
  }
  model.ridge_ = ridge_;
  return model;
}

std::vector<std::string> AppearanceGazeTrainer::subjects() const {
  std::vector<std::string> names;
  for (const auto& [subject, sums] : by_subject_) names.push_back(subject);
  return names;
}

}  // namespace gazedirector
