#pragma once

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "gazedirector/face/face.h"
#include "gazedirector/fit/energy.h"
#include "gazedirector/fit/fitting_problem.h"
#include "gazedirector/fit/landmark_model.h"
#include "gazedirector/geometry/camera.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/util/thread_pool.h"

namespace gazedirector {

struct FitOptions {
  EnergyWeights weights;
  int max_iterations = 16;        // Gauss-Newton iterations over all pyramid levels
  double tolerance = 2e-3;        // stop when an iteration lowers E by less than this fraction, twice running
  int work_width = 200;           // the fitted region is resampled to this many pixels across
  bool coarse_to_fine = true;     // start on a half-resolution, smoother image
  ParameterMask free = AllParameters();  // parameters held fixed are false
  // Annealing: the step η grows from `first_step` by `step_growth` per iteration up to 1,
  // and λ_ldmks falls to `landmark_final` of its value: landmarks guide early, pixels decide late.
  double first_step = 0.6;
  double step_growth = 0.1;
  double landmark_final = 0.5;
  bool record_history = false;    // keep every iterate (for plots)
  // After the first iteration, try a grid of gaze directions (lids following)
  // around looking into the lens and go on from the best: Gauss-Newton alone
  // can stall in the nearest local minimum. Fresh fits only; warm starts,
  // whose gaze is already close, try the smaller jump search below.
  bool gaze_search = true;
  double gaze_search_yaw = 30;    // the grid spans +-this many degrees of yaw
  double gaze_search_pitch = 20;  // and of pitch
  double gaze_search_step = 5;
  // A warm fit first tries gaze jumps of this many degrees (0: none) around
  // its start and around looking into the lens, and goes on from the best:
  // saccades outrun Gauss-Newton, and a track that slid into a wrong minimum
  // (a dark limbal ring or lashes taken for the iris) finds its way back.
  double jump_search_step = 0;
  // A fresh fit runs the coarse level from each of these gaze pitches (degrees)
  // and goes on from the best: pitch has several basins.
  std::vector<double> pitch_starts = {-10, 0, 10};
};

struct FitIteration {
  int level = 0;          // pyramid level (0 coarsest)
  EnergyTerms terms;
  Parameters phi;
  double step = 0;        // η of the accepted step
};

struct FitResult {
  Parameters phi;
  EnergyTerms terms;      // at the final Φ, finest level
  int iterations = 0;
  bool converged = false;  // stopped because E stopped falling, not at the iteration limit
  std::vector<FitIteration> history;  // with record_history: the initial Φ, then each accepted iterate
  cv::Rect2d region;       // the fitted region of the input image
  Camera work_camera;      // the camera of the working resolution
  // RMS distance between the model's and the tracker's eyelid landmarks,
  // relative to the eye's width; NaN when fitted without landmarks.
  double landmark_error = 0;
  bool good = false;       // the fit explains the image (see Fitter::Assess)
  std::string note;        // why not, when not
};

// How a crop of one eye is framed, and what is known of the head's turn.
struct EyePatchFraming {
  // The eye's corners (the canthi) as a share of the crop's width, at every
  // turn of the head: the crop is scaled to the eye. 0.76 in the Columbia
  // crops, measured on their mean; their mean crops at head poses +-30 show
  // the eye as wide as at 0, where a fixed scale would foreshorten one eye
  // by a quarter.
  double corner_distance = 0.76;
  // The head's yaw, degrees (the model's convention: Parameters::rotation_deg).
  double head_yaw = 0.0;
  // Whether head_yaw was read from the crop (AppearanceGaze) instead of given.
  bool head_yaw_read = false;

  // A crop framed as Columbia's with the head's yaw given, or read from the
  // crop by AppearanceGaze (0 where the reading has none).
  static EyePatchFraming GivenHeadYaw(double head_yaw) { return {.head_yaw = head_yaw}; }
  static EyePatchFraming ReadHeadYaw(const AppearanceReading& reading) {
    return {.head_yaw = reading.HeadYawOr(0.0), .head_yaw_read = true};
  }

  // The head yaw the eye is scaled at: head_yaw where given; a reading only
  // as far as it reads the head clearly turned, weighted by
  // 1 - exp(-(yaw / kReadingTrustDeg)^2 / 2). A frontal head's reading errs
  // by about 4 degrees, and each degree would scale the eye by about 0.5%
  // (its outer corner lies deeper than its inner one): followed fully, that
  // cost frontal heads 0.2 degrees of yaw (docs/known-gaps.md).
  double FramingYaw() const;
  static constexpr double kReadingTrustDeg = 10.0;
};

// Fits the multi-part eye-region model to images by analysis-by-synthesis
// with annealed Gauss-Newton: numerical central-difference Jacobians (two
// renders per parameter, spread over the thread pool) and exact ones for the
// appearance and light (Renderer::ExactJacobian), on a coarse-to-fine image
// pyramid.
class Fitter {
 public:
  Fitter(std::shared_ptr<const EyeRegionModel> model, FitOptions options = {},
         std::shared_ptr<ThreadPool> pool = nullptr);

  // Both eye regions of a face, from its landmarks, or from `start` (the
  // previous video frame's Φ) when given.
  FitResult FitFace(const cv::Mat& image, const Camera& camera, const Face& face, const Parameters* start = nullptr);
  // A fresh fit from the landmarks (gaze search and all) in which the
  // parameters the options hold fixed keep `known`'s values and the light
  // starts at `known`'s: a video's settled shape and texture survive a refit
  // on an unusual frame.
  FitResult RefitFace(const cv::Mat& image, const Camera& camera, const Face& face, const Parameters& known);

  // One eye region in a crop of a single eye (as the Columbia crops): the eye
  // sits at the crop's centre, framed as `framing` says. `eye` is the
  // subject's (kLeftEye is the image-right eye).
  FitResult FitEyePatch(const cv::Mat& crop, int eye, const EyePatchFraming& framing = {});
  // Where FitEyePatch starts: the eye placed by the crop's framing, mean
  // shape, the head turned by the framing's head yaw.
  Parameters EyePatchStart(cv::Size crop, int eye, const EyePatchFraming& framing = {}) const;
  static Camera EyePatchCamera(cv::Size crop);
  // The same, starting from a given gaze (pitch, yaw in degrees; the lids
  // follow), with the gaze pulled toward `appearance` (AppearanceGaze's
  // reading of the crop; none where its angles are NaN).
  FitResult FitEyePatchAt(const cv::Mat& crop, int eye, double pitch, double yaw, const EyePatchFraming& framing = {},
                          const AppearanceReading& appearance = {});

  FitOptions& options() { return options_; }
  const FitOptions& options() const { return options_; }
  const EyeRegionModel& model() const { return *model_; }

  // The numerical derivative step of parameter `index` at Φ seen by `camera`:
  // about half a pixel of motion for geometry.
  static double StepSize(int index, const Parameters& phi, const Camera& camera);

 private:
  struct Level {
    std::unique_ptr<FittingProblem> problem;
  };
  FitResult FitFaceFrom(const cv::Mat& image, const Camera& camera, const Face& face, Parameters phi, bool fresh);
  // `fresh`: not warm-started, so search gaze and try several pitches.
  FitResult Solve(std::vector<Level>& levels, Parameters phi, const ParameterMask& free, bool fresh);
  // With `search_centre` (gaze pitch, yaw in degrees), searches a grid of gazes around it after the first step.
  bool RunLevel(FittingProblem& problem, int level, int budget, const std::vector<int>& free,
                const Eigen::Vector2d* search_centre, Parameters& phi, int& iteration, std::vector<FitIteration>* history);
  // The point of a grid of gazes around `centre` with the lowest energy, from Φ.
  Parameters SearchGaze(FittingProblem& problem, const Parameters& phi, const Eigen::Vector2d& centre);
  // Φ with the gaze (pitch, yaw) of `gazes` that has the lowest energy, or Φ
  // itself where none is lower; the lids stay.
  Parameters BestGaze(FittingProblem& problem, const Parameters& phi, const std::vector<Eigen::Vector2d>& gazes);
  // A warm fit's jumps: one step each way around Φ's gaze, and a wider grid
  // around `lens` (looking into the lens).
  std::vector<Eigen::Vector2d> JumpGazes(const Parameters& phi, const Eigen::Vector2d& lens) const;
  // One Gauss-Newton linearisation at Φ: the residuals, J^T J and J^T r over `free`.
  double Linearize(FittingProblem& problem, const Parameters& phi, const std::vector<int>& free,
                   Eigen::MatrixXd& normal, Eigen::VectorXd& gradient);
  // JᵀJ (full) and Jᵀr of the current Jacobian and residuals.
  void NormalEquations(Eigen::MatrixXd& normal, Eigen::VectorXd& gradient) const;
  std::vector<Level> Pyramid(const cv::Mat& image, const cv::Rect2d& region, const Camera& camera,
                             const LandmarkModel& landmarks, const std::vector<Eigen::Vector2d>& targets,
                             const std::vector<double>& weights, std::array<bool, 2> eyes, double scale) const;
  // The exact columns (Renderer::ExactJacobian), (column in the Jacobian,
  // index in Renderer::ExactParameters) each, from Φ's render in main().
  void ExactColumns(const FittingProblem& problem, const Parameters& phi, const std::vector<int>& free,
                    const std::vector<std::pair<int, int>>& exact);
  void Assess(FitResult& result, const FittingProblem& problem) const;
  // The workspace that holds Φ's render (and the line search's trials), and
  // each thread's own for the other renders.
  EvaluationWorkspace& main() const { return *workspaces_.front(); }
  EvaluationWorkspace& scratch(int worker) const { return *workspaces_[worker + 1]; }

  std::shared_ptr<const EyeRegionModel> model_;
  FitOptions options_;
  std::shared_ptr<ThreadPool> pool_;
  LandmarkModel landmarks_;
  std::vector<std::unique_ptr<EvaluationWorkspace>> workspaces_;
  Eigen::MatrixXf jacobian_;
  Eigen::MatrixXf exact_jacobian_;
  std::vector<float> pixel_scales_;  // each domain pixel's weight in the residuals, for the exact columns
  Eigen::VectorXf residuals_;
};

// The working width of eye-patch fits of the 64 px Columbia crops: resampled
// to 128 px, where their gaze is read best (docs/known-gaps.md, session 31).
inline constexpr int kEyePatchWorkWidth = 128;

// How far the lids and the gaze may pitch either way, degrees.
inline constexpr double kEyelidPitchBoundDeg = 40;
inline constexpr double kGazePitchBoundDeg = 45;

// Clamps Φ to plausible values (PCA within 3 standard deviations, gaze
// within the eye's range, lids within kEyelidPitchBoundDeg, positive colours
// and light).
void ClampToBounds(Parameters& phi);

}  // namespace gazedirector
