#pragma once

#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "gazedirector/fit/appearance_gaze.h"
#include "gazedirector/fit/energy.h"
#include "gazedirector/fit/landmark_model.h"
#include "gazedirector/geometry/camera.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/render/renderer.h"

namespace gazedirector {

// What one thread needs to evaluate the energy: a renderer and its buffers.
struct EvaluationWorkspace {
  explicit EvaluationWorkspace(std::shared_ptr<const EyeRegionModel> model) : renderer(std::move(model)) {}
  // Renders Φ into `buffers` unless they already hold its render with this
  // camera and these eyes: Gauss-Newton evaluates the accepted trial again
  // at the start of the next iteration, and linearises at the same Φ.
  void Render(const Parameters& phi, const Camera& camera, std::array<bool, 2> eyes);

  Renderer renderer;
  RenderBuffers buffers;
  std::vector<int> foreground_index;  // pixel -> row of buffers.colour, or -1
  std::vector<Eigen::Vector2d> landmarks;
  Eigen::VectorXf plus, minus;  // residuals of the two renders of a central difference

 private:
  bool holds_render_ = false;
  Parameters rendered_phi_;
  Camera rendered_camera_;
  std::array<bool, 2> rendered_eyes_{};
};

// One image to explain: the observed region at working resolution, its
// camera, the landmarks the face tracker found there, and the weights.
// Evaluates E(Φ) as a sum of squared residuals:
//   image      3 per pixel of the domain: (I_syn - I_obs) / sqrt|P|, capped at sqrt(T)
//   landmarks  2 per landmark: (l' - l) sqrt(λ / |P|)
//   stats      sqrt(λ_geo) β, sqrt(λ_tex) τ
//   pose       sqrt(λ_pose) (θ_lid - θ_p), sqrt(λ_verg) θ_v, sqrt(λ_close) θ_close,
//              sqrt(λ_app,p) (θ_p - θ_app,p), sqrt(λ_app,y) (θ_y - θ_app,y) where
//              the crop's appearance gives a reading θ_app (λ_app,y raised
//              by appearance_turned_factor as the head reads turned)
class FittingProblem {
 public:
  FittingProblem(std::shared_ptr<const EyeRegionModel> model, const cv::Mat& observed_rgb, const Camera& camera,
                 const LandmarkModel& landmark_model, std::vector<Eigen::Vector2d> target_landmarks,
                 std::vector<double> landmark_weights, const EnergyWeights& weights, std::array<bool, 2> eyes);

  // The pixels whose residuals the next Gauss-Newton step uses: those the
  // model covers at the current Φ, grown by `margin` pixels so that pixels
  // the model may move onto are included.
  void SetDomain(const RenderBuffers& current, int margin);
  int num_residuals() const;
  // The residuals after the texture prior's: eyelid-gaze, vergence, closure,
  // appearance pitch, appearance yaw.
  static constexpr int kPoseResiduals = 5;
  int num_image_residuals() const { return 3 * static_cast<int>(domain_.size()); }
  const std::vector<int>& domain() const { return domain_; }

  // Renders Φ and returns its energy; fills `residuals` when given.
  EnergyTerms Evaluate(const Parameters& phi, EvaluationWorkspace& work, Eigen::VectorXf* residuals) const;

  // The per-pixel scale applied to colour differences at the last Evaluate
  // into `work` (1/sqrt|P|, less where the error was capped), for turning
  // d(colour)/dΦ into d(residual)/dΦ.
  float PixelScale(const EvaluationWorkspace& work, int pixel) const;

  const Camera& camera() const { return camera_; }
  const cv::Mat& observed() const { return observed_; }
  const EnergyWeights& weights() const { return weights_; }
  EnergyWeights& weights() { return weights_; }
  std::array<bool, 2> eyes() const { return eyes_; }
  const LandmarkModel& landmark_model() const { return landmark_model_; }
  const std::vector<Eigen::Vector2d>& target_landmarks() const { return targets_; }
  // The gaze the crop's appearance reads (AppearanceGaze), pulled toward with
  // weights λ_app; NaN angles (the default) for none.
  void set_appearance(const AppearanceReading& reading) { appearance_ = reading; }
  const AppearanceReading& appearance() const { return appearance_; }

 private:
  std::shared_ptr<const EyeRegionModel> model_;
  cv::Mat observed_;  // CV_32FC3, RGB in [0, 1]
  Camera camera_;
  LandmarkModel landmark_model_;
  std::vector<Eigen::Vector2d> targets_;
  std::vector<double> landmark_weights_;  // per landmark, multiplying λ_ldmks
  EnergyWeights weights_;
  std::array<bool, 2> eyes_;
  std::vector<int> domain_;
  AppearanceReading appearance_;
};

}  // namespace gazedirector
