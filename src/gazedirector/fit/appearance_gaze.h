#pragma once

#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

namespace gazedirector {

// A gaze direction read from an eye crop's appearance: degrees relative to
// the head, pitch positive up, yaw as EyeRegionModel::EyeYaw. NaN: no reading.
struct AppearanceReading {
  double pitch = std::numeric_limits<double>::quiet_NaN();
  double yaw = std::numeric_limits<double>::quiet_NaN();
};

// Reads the gaze of an eye crop framed as the Columbia crops are (the eye at
// the centre, its corners about 0.76 of the width apart) from its pixels: two
// ridge regressions, for pitch and for yaw, on the band of the crop that the
// eye and its lids occupy, trained on labelled crops of other people.
//
// Why: fitted to one small crop, the model reads a person's lids as gaze (an
// upper lid that rests low reads as looking down), a bias that differs from
// person to person and that no setting of the energy removes
// (docs/known-gaps.md). Yaw is read better by the fit, but the crops of one
// data set share a yaw offset that the fit of a single crop cannot see, and a
// crop barely shows how far the head is turned. Trained on many people, the
// regressions learn what each gaze looks like across lid shapes. The fit pulls its gaze toward this reading
// (EnergyWeights::appearance_pitch and appearance_yaw), so the estimate stays
// the fitted model's, with a prior that knows about people.
class AppearanceGaze {
 public:
  // The crop is shrunk to kGrid x kGrid grey pixels, and the band of rows
  // 3-10 and columns 2-13 (the eye and lids) is standardised to zero mean and
  // unit variance. The subject's left eye (kLeftEye) is mirrored, so that both
  // eyes present their inner corner on the same side; a last feature says
  // which eye it is (+1 right, -1 left), so that an offset that is the same
  // on the image for both eyes can be learned although the mirroring turns it
  // around for one of them.
  static constexpr int kGrid = 16;
  static int NumFeatures();
  static Eigen::VectorXd Features(const cv::Mat& crop, int eye);

  AppearanceReading Read(const cv::Mat& crop, int eye) const;

  // The subjects it was trained on (an evaluation on them would be in-sample).
  const std::vector<std::string>& subjects() const { return subjects_; }
  double ridge() const { return ridge_; }
  // The crops each regression learned from.
  int pitch_samples() const { return pitch_samples_; }
  int yaw_samples() const { return yaw_samples_; }

  nlohmann::json ToJson() const;
  // Fails (ExitCode::kAssets) on a file that is missing or not such a model.
  static AppearanceGaze Load(const std::filesystem::path& path);
  void Save(const std::filesystem::path& path) const;

 private:
  friend class AppearanceGazeTrainer;
  // One column per angle (pitch, then yaw in the mirrored frame): a weight
  // per feature, then the intercept.
  Eigen::Matrix<double, Eigen::Dynamic, 2> weights_;
  std::vector<std::string> subjects_;
  double ridge_ = 0;
  int pitch_samples_ = 0, yaw_samples_ = 0;
};

// Accumulates each subject's normal equations, so that a model that leaves
// any one subject out (for an honest evaluation on that subject) is a single
// small solve.
class AppearanceGazeTrainer {
 public:
  // `ridge`: the penalty on the squared weights (the features are standardised).
  explicit AppearanceGazeTrainer(double ridge = 10.0);
  // The crop as read from its file (colour or grey), its gaze relative to the
  // head; a NaN angle leaves the crop out of that angle's regression.
  void Add(const std::string& subject, const cv::Mat& crop, int eye, double pitch_deg, double yaw_deg);
  // Trained on every subject added except `left_out` (none when empty).
  AppearanceGaze Solve(const std::string& left_out = "") const;
  std::vector<std::string> subjects() const;

 private:
  // One regression's sums.
  struct Sums {
    Eigen::MatrixXd normal;  // XᵀX with the intercept's column
    Eigen::VectorXd rhs;     // Xᵀy
    int samples = 0;
    void Add(const Eigen::VectorXd& row, double label);
  };
  struct SubjectSums {
    Sums pitch, yaw;
  };
  Eigen::VectorXd SolveOne(const std::string& left_out, Sums SubjectSums::*angle, const char* name, int& samples) const;
  std::map<std::string, SubjectSums> by_subject_;
  double ridge_;
};

}  // namespace gazedirector
