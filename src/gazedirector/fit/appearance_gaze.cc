#include "gazedirector/fit/appearance_gaze.h"

#include <cmath>
#include <fstream>

#include <Eigen/Cholesky>
#include <opencv2/imgproc.hpp>

#include "gazedirector/io/atomic_output.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace fs = std::filesystem;
namespace {

// The band of the kGrid x kGrid crop that holds the eye and its lids.
constexpr int kFirstRow = 3, kLastRow = 10, kFirstColumn = 2, kLastColumn = 13;
constexpr int kBandRows = kLastRow - kFirstRow + 1, kBandColumns = kLastColumn - kFirstColumn + 1;
constexpr const char* kFormat = "gazedirector-appearance-gaze-1";

// Yaw is learned in the mirrored frame, where both eyes turn alike.
double MirroredYawSign(int eye) { return eye == kLeftEye ? -1.0 : 1.0; }

// A regression's input: the features, then 1 for the intercept.
Eigen::VectorXd RowOf(const cv::Mat& crop, int eye) {
  Eigen::VectorXd row(AppearanceGaze::NumFeatures() + 1);
  row << AppearanceGaze::Features(crop, eye), 1.0;
  return row;
}

}  // namespace

int AppearanceGaze::NumFeatures() { return kBandRows * kBandColumns + 1; }

Eigen::VectorXd AppearanceGaze::Features(const cv::Mat& crop, int eye) {
  if (crop.empty()) Fail(ExitCode::kBadInput, "appearance gaze: empty crop");
  cv::Mat grey;
  if (crop.channels() == 3) {
    cv::cvtColor(crop, grey, cv::COLOR_BGR2GRAY);
  } else if (crop.channels() == 1) {
    grey = crop;
  } else {
    Fail(ExitCode::kBadInput, "appearance gaze: a crop needs 1 or 3 channels, not {}", crop.channels());
  }
  cv::Mat small;
  cv::resize(grey, small, cv::Size(kGrid, kGrid), 0, 0, cv::INTER_AREA);
  if (eye == kLeftEye) cv::flip(small, small, 1);
  cv::Mat band;
  small(cv::Rect(kFirstColumn, kFirstRow, kBandColumns, kBandRows)).convertTo(band, CV_64F);
  cv::Scalar mean, deviation;
  cv::meanStdDev(band, mean, deviation);
  Eigen::VectorXd features(NumFeatures());
  for (int y = 0; y < kBandRows; ++y) {
    for (int x = 0; x < kBandColumns; ++x) {
      features[y * kBandColumns + x] = (band.at<double>(y, x) - mean[0]) / (deviation[0] + 1e-6);
    }
  }
  features[NumFeatures() - 1] = MirroredYawSign(eye);
  return features;
}

AppearanceReading AppearanceGaze::Read(const cv::Mat& crop, int eye) const {
  const Eigen::Vector2d angles = weights_.transpose() * RowOf(crop, eye);
  return {angles[0], MirroredYawSign(eye) * angles[1]};
}

nlohmann::json AppearanceGaze::ToJson() const {
  auto column = [&](int c) { return std::vector<double>(weights_.col(c).data(), weights_.col(c).data() + weights_.rows()); };
  return {{"format", kFormat},
          {"grid", kGrid},
          {"band", {kFirstRow, kLastRow, kFirstColumn, kLastColumn}},
          {"ridge", ridge_},
          {"pitch_samples", pitch_samples_},
          {"yaw_samples", yaw_samples_},
          {"subjects", subjects_},
          {"pitch_weights", column(0)},
          {"mirrored_yaw_weights", column(1)}};
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
        json.at("band") != nlohmann::json({kFirstRow, kLastRow, kFirstColumn, kLastColumn})) {
      Fail(ExitCode::kAssets, "{}: not a {} model", path.string(), kFormat);
    }
    model.weights_.resize(NumFeatures() + 1, 2);
    int c = 0;
    for (const char* key : {"pitch_weights", "mirrored_yaw_weights"}) {
      const std::vector<double> weights = json.at(key).get<std::vector<double>>();
      if (static_cast<int>(weights.size()) != NumFeatures() + 1) {
        Fail(ExitCode::kAssets, "{}: {} {} where {} were expected", path.string(), weights.size(), key,
             NumFeatures() + 1);
      }
      model.weights_.col(c++) = Eigen::Map<const Eigen::VectorXd>(weights.data(), NumFeatures() + 1);
    }
    model.subjects_ = json.at("subjects").get<std::vector<std::string>>();
    model.ridge_ = json.at("ridge").get<double>();
    model.pitch_samples_ = json.at("pitch_samples").get<int>();
    model.yaw_samples_ = json.at("yaw_samples").get<int>();
  } catch (const nlohmann::json::exception& e) {
    Fail(ExitCode::kAssets, "{}: not a valid appearance gaze model ({})", path.string(), e.what());
  }
  if (!model.weights_.allFinite()) Fail(ExitCode::kAssets, "{}: weights are not finite", path.string());
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
  ++samples;
}

void AppearanceGazeTrainer::Add(const std::string& subject, const cv::Mat& crop, int eye, double pitch_deg,
                                double yaw_deg) {
  const Eigen::VectorXd row = RowOf(crop, eye);
  SubjectSums& sums = by_subject_[subject];
  sums.pitch.Add(row, pitch_deg);
  sums.yaw.Add(row, MirroredYawSign(eye) * yaw_deg);
}

Eigen::VectorXd AppearanceGazeTrainer::SolveOne(const std::string& left_out, Sums SubjectSums::*angle,
                                                const char* name, int& samples) const {
  const int n = AppearanceGaze::NumFeatures();
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n + 1, n + 1);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + 1);
  samples = 0;
  for (const auto& [subject, sums] : by_subject_) {
    const Sums& these = sums.*angle;
    if (subject == left_out || these.samples == 0) continue;
    normal += these.normal;
    rhs += these.rhs;
    samples += these.samples;
  }
  if (samples == 0) Fail(ExitCode::kBadInput, "appearance gaze: no training crops labelled with {}", name);
  // Neither the intercept nor the eye's side is penalised: they carry offsets.
  normal.diagonal().head(n - 1).array() += ridge_;
  return normal.selfadjointView<Eigen::Lower>().ldlt().solve(rhs);
}

AppearanceGaze AppearanceGazeTrainer::Solve(const std::string& left_out) const {
  AppearanceGaze model;
  model.weights_.resize(AppearanceGaze::NumFeatures() + 1, 2);
  model.weights_.col(0) = SolveOne(left_out, &SubjectSums::pitch, "pitch", model.pitch_samples_);
  model.weights_.col(1) = SolveOne(left_out, &SubjectSums::yaw, "yaw", model.yaw_samples_);
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
