#include "gazedirector/fit/appearance_pitch.h"

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
constexpr const char* kFormat = "gazedirector-appearance-pitch-1";

}  // namespace

int AppearancePitch::NumFeatures() { return kBandRows * kBandColumns; }

Eigen::VectorXd AppearancePitch::Features(const cv::Mat& crop, int eye) {
  if (crop.empty()) Fail(ExitCode::kBadInput, "appearance pitch: empty crop");
  cv::Mat grey;
  if (crop.channels() == 3) {
    cv::cvtColor(crop, grey, cv::COLOR_BGR2GRAY);
  } else if (crop.channels() == 1) {
    grey = crop;
  } else {
    Fail(ExitCode::kBadInput, "appearance pitch: a crop needs 1 or 3 channels, not {}", crop.channels());
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
  return features;
}

double AppearancePitch::Predict(const cv::Mat& crop, int eye) const {
  const int n = NumFeatures();
  return weights_.head(n).dot(Features(crop, eye)) + weights_[n];
}

nlohmann::json AppearancePitch::ToJson() const {
  return {{"format", kFormat},
          {"grid", kGrid},
          {"band", {kFirstRow, kLastRow, kFirstColumn, kLastColumn}},
          {"ridge", ridge_},
          {"samples", samples_},
          {"subjects", subjects_},
          {"weights", std::vector<double>(weights_.data(), weights_.data() + weights_.size())}};
}

AppearancePitch AppearancePitch::Load(const fs::path& path) {
  std::ifstream stream(path);
  if (!stream) {
    Fail(ExitCode::kAssets, "{}: cannot read the appearance pitch model (the repository's models/ folder holds it)",
         path.string());
  }
  AppearancePitch model;
  try {
    const nlohmann::json json = nlohmann::json::parse(stream);
    if (json.at("format") != kFormat || json.at("grid") != kGrid ||
        json.at("band") != nlohmann::json({kFirstRow, kLastRow, kFirstColumn, kLastColumn})) {
      Fail(ExitCode::kAssets, "{}: not a {} model", path.string(), kFormat);
    }
    const std::vector<double> weights = json.at("weights").get<std::vector<double>>();
    if (static_cast<int>(weights.size()) != NumFeatures() + 1) {
      Fail(ExitCode::kAssets, "{}: {} weights where {} were expected", path.string(), weights.size(), NumFeatures() + 1);
    }
    model.weights_ = Eigen::Map<const Eigen::VectorXd>(weights.data(), static_cast<Eigen::Index>(weights.size()));
    model.subjects_ = json.at("subjects").get<std::vector<std::string>>();
    model.ridge_ = json.at("ridge").get<double>();
    model.samples_ = json.at("samples").get<int>();
  } catch (const nlohmann::json::exception& e) {
    Fail(ExitCode::kAssets, "{}: not a valid appearance pitch model ({})", path.string(), e.what());
  }
  if (!model.weights_.allFinite()) Fail(ExitCode::kAssets, "{}: weights are not finite", path.string());
  return model;
}

void AppearancePitch::Save(const fs::path& path) const { WriteTextFile(path, ToJson().dump(1) + "\n"); }

AppearancePitchTrainer::AppearancePitchTrainer(double ridge) : ridge_(ridge) {}

void AppearancePitchTrainer::Add(const std::string& subject, const cv::Mat& crop, int eye, double pitch_deg) {
  const int n = AppearancePitch::NumFeatures();
  Eigen::VectorXd row(n + 1);
  row.head(n) = AppearancePitch::Features(crop, eye);
  row[n] = 1.0;
  Sums& sums = by_subject_[subject];
  if (sums.samples == 0) {
    sums.normal.setZero(n + 1, n + 1);
    sums.rhs.setZero(n + 1);
  }
  sums.normal.selfadjointView<Eigen::Lower>().rankUpdate(row);
  sums.rhs += pitch_deg * row;
  ++sums.samples;
}

AppearancePitch AppearancePitchTrainer::Solve(const std::string& left_out) const {
  const int n = AppearancePitch::NumFeatures();
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n + 1, n + 1);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + 1);
  AppearancePitch model;
  for (const auto& [subject, sums] : by_subject_) {
    if (subject == left_out) continue;
    normal += sums.normal;
    rhs += sums.rhs;
    model.samples_ += sums.samples;
    model.subjects_.push_back(subject);
  }
  if (model.samples_ == 0) Fail(ExitCode::kBadInput, "appearance pitch: no training crops");
  normal.diagonal().head(n).array() += ridge_;  // the intercept is not penalised
  model.weights_ = normal.selfadjointView<Eigen::Lower>().ldlt().solve(rhs);
  model.ridge_ = ridge_;
  return model;
}

std::vector<std::string> AppearancePitchTrainer::subjects() const {
  std::vector<std::string> names;
  for (const auto& [subject, sums] : by_subject_) names.push_back(subject);
  return names;
}

}  // namespace gazedirector
