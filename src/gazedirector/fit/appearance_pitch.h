#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

namespace gazedirector {

// Reads the gaze pitch of an eye crop framed as the Columbia crops are (the
// eye at the centre, its corners about 0.76 of the width apart) from its
// pixels: a ridge regression on the band of the crop that the eye and its
// lids occupy, trained on labelled crops of other people.
//
// Why: fitted to one small crop, the model reads a person's lids as gaze (an
// upper lid that rests low reads as looking down), a bias that differs from
// person to person and that no setting of the energy removes
// (docs/known-gaps.md). Trained on many people, the regression learns what
// each pitch looks like across lid shapes. The fit pulls its gaze pitch
// toward this reading (EnergyWeights::appearance_pitch), so the estimate stays
// the fitted model's, with a prior that knows about people.
class AppearancePitch {
 public:
  // The crop is shrunk to kGrid x kGrid grey pixels, and the band of rows
  // 3-10 and columns 2-13 (the eye and lids) is standardised to zero mean and
  // unit variance. The subject's left eye (kLeftEye) is mirrored, so that both
  // eyes present their inner corner on the same side.
  static constexpr int kGrid = 16;
  static int NumFeatures();
  static Eigen::VectorXd Features(const cv::Mat& crop, int eye);

  // Degrees, positive up, relative to the head.
  double Predict(const cv::Mat& crop, int eye) const;

  // The subjects it was trained on (an evaluation on them would be in-sample).
  const std::vector<std::string>& subjects() const { return subjects_; }
  double ridge() const { return ridge_; }
  int samples() const { return samples_; }

  nlohmann::json ToJson() const;
  // Fails (ExitCode::kAssets) on a file that is missing or not such a model.
  static AppearancePitch Load(const std::filesystem::path& path);
  void Save(const std::filesystem::path& path) const;

 private:
  friend class AppearancePitchTrainer;
  Eigen::VectorXd weights_;  // one per feature, then the intercept
  std::vector<std::string> subjects_;
  double ridge_ = 0;
  int samples_ = 0;
};

// Accumulates each subject's normal equations, so that a model that leaves
// any one subject out (for an honest evaluation on that subject) is a single
// small solve.
class AppearancePitchTrainer {
 public:
  // `ridge`: the penalty on the squared weights (the features are standardised).
  explicit AppearancePitchTrainer(double ridge = 10.0);
  void Add(const std::string& subject, const cv::Mat& crop, int eye, double pitch_deg);
  // Trained on every subject added except `left_out` (none when empty).
  AppearancePitch Solve(const std::string& left_out = "") const;
  std::vector<std::string> subjects() const;

 private:
  struct Sums {
    Eigen::MatrixXd normal;  // XᵀX with the intercept's column
    Eigen::VectorXd rhs;     // Xᵀy
    int samples = 0;
  };
  std::map<std::string, Sums> by_subject_;
  double ridge_;
};

}  // namespace gazedirector
