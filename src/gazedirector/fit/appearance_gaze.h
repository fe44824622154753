#pragma once

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

namespace gazedirector {

// What an eye crop's appearance reads, in degrees: the gaze relative to the
// head (pitch positive up, yaw as EyeRegionModel::EyeYaw) and the head's yaw
// in the camera (Parameters::rotation_deg().y()). NaN: no reading.
struct AppearanceReading {
  double pitch = std::numeric_limits<double>::quiet_NaN();
  double yaw = std::numeric_limits<double>::quiet_NaN();
  double head_yaw = std::numeric_limits<double>::quiet_NaN();
  // How frontal the head reads: 1 where it faces the camera, toward 0 as it
  // turns (a Gaussian of width AppearanceGaze::kFrontalWidthDeg in head_yaw).
  double frontal = 1.0;
  // Where an eye patch's fit starts its head yaw: the reading, or `fallback`.
  double HeadYawOr(double fallback) const { return std::isnan(head_yaw) ? fallback : head_yaw; }
};

// A training crop's labels, in the same frames; a NaN leaves the crop out of
// the regressions that learn that angle.
struct AppearanceLabel {
  double pitch = std::numeric_limits<double>::quiet_NaN();
  double yaw = std::numeric_limits<double>::quiet_NaN();
  double head_yaw = std::numeric_limits<double>::quiet_NaN();
};

// Reads gaze and head yaw from an eye crop framed as the Columbia crops are
// (the eye at the centre, its corners about 0.76 of the width apart):
// Gaussian-kernel ridge regressions on labelled crops of other people.
//
// Why: fitted to one small crop, the model reads a person's lids as gaze (an
// upper lid that rests low reads as looking down), a bias that differs from
// person to person and that no setting of the energy removes
// (docs/known-gaps.md). Yaw is read better by the fit, but the crops of one
// data set share a yaw offset that the fit of a single crop cannot see, and
// the fit barely sees how far the head is turned, which decides what its
// gaze means relative to the head. Trained on many people, the regressions
// learn what each gaze and each turn of the head look like across lid
// shapes. The fit starts its head yaw at the reading and pulls its gaze
// toward the gaze read (EnergyWeights::appearance_pitch and appearance_yaw),
// so the estimate stays the fitted model's, with a prior that knows about
// people.
//
// Each regression weighs the training crops (the exemplars) by a Gaussian of
// their distance to the crop read, in the whole crop's standardised features
// (CropFeatures), each weighed by how much more it tells the head's turn than
// the person (AppearanceGazeTrainer::TurnOverPersonWeights): a crop is read
// like the crops that look like it at its turn. Linear
// regressions on the same features erred more (per crop, people left out:
// pitch 3.81 against 3.59 degrees, the head's yaw 5.74 against 5.14), since
// what a gaze looks like changes with the lids, the head's turn and the
// light. Five regressions:
//   pitch        learned from every crop;
//   frontal yaw  learned from crops whose head faces the camera (head yaw
//                0), where it reads best;
//   camera yaw   the gaze's yaw relative to the camera, and
//   turned yaw   the gaze's yaw relative to the head, both learned from
//                every crop, their kernel also weighing how far each
//                exemplar's head was turned against the turn given (so that
//                the eye nearer the camera and the one farther away are each
//                read like their own kind);
//   head yaw     learned from every crop.
// The yaw read is the frontal yaw where the head yaw is near 0, blended by a
// Gaussian of width kFrontalYawWidthDeg in the head yaw, and where the head
// is turned: with the head's yaw given, the camera yaw turned into the
// head's frame by it (a crop shows where the eye looks relative to the
// camera better than how far the head is turned: each eye at head yaw +-30,
// people left out, errs by 3.6-4.8 degrees so, 4.0-5.2 read relative to
// the head); with the head's yaw read, the turned yaw, which does not pass
// the reading's error (6-7 degrees at head yaw +-30) whole into the gaze:
// per photo, people left out, 4.62 degrees of yaw over all head poses read
// relative to the camera and turned, 3.98 read relative to the head
// (docs/known-gaps.md, session 48).
class AppearanceGaze {
 public:
  // The eye band: the crop shrunk to kGrid x kGrid grey pixels, and the band
  // of rows 3-10 and columns 2-13 (the eye and lids) standardised to zero
  // mean and unit variance. The subject's left eye (kLeftEye) is mirrored, so
  // that both eyes present their inner corner on the same side; a last
  // feature says which eye it is (+1 right, -1 left), so that an offset that
  // is the same on the image for both eyes can be learned although the
  // mirroring turns it around for one of them.
  static constexpr int kGrid = 16;
  static int NumBandFeatures();
  static Eigen::VectorXd BandFeatures(const cv::Mat& crop, int eye);
  // The whole crop: the band's pixels, then a histogram of oriented gradients
  // of the (mirrored) crop shrunk to kHogSize pixels, which sees the skin and
  // nose beside the eye that tell a turned head, then the eye's side.
  static constexpr int kHogSize = 32;
  static int NumCropFeatures();
  static Eigen::VectorXd CropFeatures(const cv::Mat& crop, int eye);
  // About the head-yaw reading's own error, degrees.
  static constexpr double kFrontalWidthDeg = 7.0;
  // The frontal yaw's share of the yaw read falls off faster: learned from
  // heads facing the camera only, it misreads a head turned by a few degrees
  // more than the turned yaw does (fits over all head poses 3.95 degrees of
  // yaw with a share as wide as kFrontalWidthDeg, 3.79 with this).
  static constexpr double kFrontalYawWidthDeg = 4.0;

  // The head's yaw alone, as the regression reads it.
  double ReadHeadYaw(const cv::Mat& crop, int eye) const;
  // The gaze, given the head's yaw, known.
  AppearanceReading Read(const cv::Mat& crop, int eye, double head_yaw) const;
  // The gaze, given the head's yaw as read: from this crop, or better from
  // both eyes of the face (the mean of their ReadHeadYaw). The regression
  // reads people it was not trained on short of the turns it learned (a 30
  // degree turn as about 23 on Columbia), and a turned eye's gaze relative to
  // the head falls short with it, so the turned yaw's kernel weighs the
  // exemplars' turns against the reading divided by head_yaw_slope(). How
  // frontal the head reads and where the fit starts keep the reading
  // itself, which is less noisy near 0.
  AppearanceReading ReadGivenHeadReading(const cv::Mat& crop, int eye, double read_head_yaw) const;
  AppearanceReading Read(const cv::Mat& crop, int eye) const;
  // How much of a head's yaw the regression reads, on average, for people it
  // was not trained on: each training subject read by a regression trained
  // without them, the least-squares slope of reading on label (through 0).
  double head_yaw_slope() const { return head_yaw_slope_; }

  // The subjects it was trained on (an evaluation on them would be in-sample).
  const std::vector<std::string>& subjects() const { return subjects_; }
  double ridge() const { return ridge_; }
  // The crops each regression learned from.
  struct Samples {
    int pitch = 0, frontal_yaw = 0, camera_yaw = 0, turned_yaw = 0, head_yaw = 0;
    bool operator==(const Samples&) const = default;
  };
  const Samples& samples() const { return samples_; }

  // The model as CBOR: a JSON document whose exemplars are a binary block of
  // little-endian floats (a text file of them would be ten times larger).
  // Fails (ExitCode::kAssets) on a file that is missing or not such a model.
  static AppearanceGaze Load(const std::filesystem::path& path);
  void Save(const std::filesystem::path& path) const;

 private:
  friend class AppearanceGazeTrainer;
  struct Regression {
    Eigen::VectorXd weights;  // one per exemplar; 0 for those it did not learn from
    double offset = 0;
  };
  // A crop's squared distances to the exemplars, in the kernel's units.
  Eigen::VectorXd SquaredDistances(const Eigen::VectorXd& features, int eye) const;
  double Evaluate(const Regression& regression, const Eigen::VectorXd& kernel) const;
  Eigen::VectorXd Kernel(const Eigen::VectorXd& squared_distances) const;
  // The kernel with the exemplars' head turns weighed against `head_yaw`.
  Eigen::VectorXd TurnedKernel(const Eigen::VectorXd& squared_distances, int eye, double head_yaw) const;
  // On a crop's squared distances: the head's yaw as read, and the gaze
  // with the head's yaw given or read.
  double HeadYawOf(const Eigen::VectorXd& squared_distances, int eye) const;
  enum class HeadYaw { kGiven, kRead };
  AppearanceReading ReadAt(const Eigen::VectorXd& squared_distances, int eye, double head_yaw,
                           HeadYaw head_yaw_is) const;
  // Each exemplar's standardised features (the eye's side last), and the
  // head's yaw it was taken at in the mirrored frame, over kTurnScaleDeg.
  Eigen::MatrixXf exemplars_;
  Eigen::VectorXd exemplar_turns_;
  Eigen::VectorXd feature_mean_, feature_scale_;  // of the pixels and gradients
  double kernel_width_ = 1;  // twice the median squared distance between exemplars
  // Yaws are learned in the mirrored frame, where both eyes turn alike.
  Regression pitch_, frontal_yaw_, camera_yaw_, turned_yaw_, head_yaw_;
  double head_yaw_slope_ = 1.0;
  std::vector<std::string> subjects_;
  double ridge_ = 0;
  Samples samples_;
};

// Keeps each subject's crops (their features and labels), so that a model
// that leaves any one subject out (for an honest evaluation on that subject)
// can be solved without reading them again.
class AppearanceGazeTrainer {
 public:
  // `ridge`: the penalty on the regressions' squared weights in the kernel's
  // feature space.
  explicit AppearanceGazeTrainer(double ridge = 0.1);
  // The crop as read from its file (colour or grey) and its labels.
  void Add(const std::string& subject, const cv::Mat& crop, int eye, const AppearanceLabel& label);
  // Trained on every subject added except `left_out` (none when empty).
  AppearanceGaze Solve(const std::string& left_out = "") const;
  std::vector<std::string> subjects() const;
  bool Has(const std::string& subject) const { return by_subject_.count(subject) > 0; }

  // How much each feature (a column of `standardised`, one row per crop)
  // tells the head's turn against how much it tells who the person is: the
  // square root of the variance of the mean feature at each turn (`turns`,
  // degrees, grouped to the degree; NaN: unknown) over the variance of each
  // subject's mean at a turn about that turn's mean, scaled to a root mean
  // square of 1. Ones where the turns or the subjects are too few to tell.
  // Solve weighs the kernel's features by it.
  static Eigen::VectorXd TurnOverPersonWeights(const Eigen::MatrixXd& standardised, const std::vector<double>& turns,
                                               const std::vector<int>& subject_of);

 private:
  struct Sample {
    Eigen::VectorXd features;  // CropFeatures
    // In the mirrored frame; NaN where unlabelled.
    double pitch, frontal_yaw, camera_yaw, turned_yaw, head_yaw;
  };
  // Sets the model's exemplars (the samples' features standardised, weighed
  // by TurnOverPersonWeights, the eye's side last) and their head turns.
  static void SetExemplars(const std::vector<const Sample*>& samples, const std::vector<int>& subject_of,
                           AppearanceGaze& model);
  // AppearanceGaze::head_yaw_slope() of the head-yaw regression whose factor
  // and weights these are.
  static double HeadYawSlope(const Eigen::LLT<Eigen::MatrixXd>& factor, const std::vector<Eigen::Index>& rows,
                             const std::vector<const Sample*>& samples, const std::vector<int>& subject_of,
                             const AppearanceGaze::Regression& head);
  std::map<std::string, std::vector<Sample>> by_subject_;
  double ridge_;
};

}  // namespace gazedirector
