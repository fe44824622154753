#include "gazedirector/fit/fitter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Dense>
#include <opencv2/imgproc.hpp>

#include "gazedirector/fit/initialization.h"
#include "gazedirector/geometry/rotation.h"
#include "gazedirector/model/eye_region_topology.h"
#include "gazedirector/render/model_bounds.h"
#include "gazedirector/util/gram_matrix.h"

namespace gazedirector {
namespace {

constexpr int kDomainMargin = 2;   // pixels around the model whose residuals a step watches
constexpr int kMaxBacktracks = 4;  // halvings of η before a step is given up
constexpr double kDamping = 1e-4;  // Levenberg-Marquardt damping relative to the diagonal

// The observed region at a working scale: float RGB in [0, 1].
cv::Mat ObservedRegion(const cv::Mat& image, const cv::Rect& region, cv::Size size) {
  cv::Mat resized;
  const bool shrinking = size.width < region.width;
  cv::resize(image(region), resized, size, 0, 0, shrinking ? cv::INTER_AREA : cv::INTER_LINEAR);
  cv::Mat rgb;
  cv::cvtColor(resized, rgb, cv::COLOR_BGR2RGB);
  rgb.convertTo(rgb, CV_32FC3, 1.0 / 255.0);
  return rgb;
}

double GroupWeight(LandmarkGroup group, const EnergyWeights& weights) {
  switch (group) {
    case LandmarkGroup::kBrow: return weights.brow_factor;
    case LandmarkGroup::kNose: return weights.nose_factor;
    default: return 1.0;
  }
}

// Gaze pitch and yaw in the head that look from the fitted eyes into the lens.
Eigen::Vector2d LookingIntoTheLens(const Parameters& phi, std::array<bool, 2> eyes) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int eye = 0; eye < 2; ++eye) {
    if (eyes[eye]) centre += EyeRegionModel::EyeCentreInHead(phi, eye);
  }
  centre /= std::max(1, eyes[0] + eyes[1]);
  return EyeRegionModel::PitchYawInHead(EyeRegionModel::PointInHead(phi, Eigen::Vector3d::Zero()) - centre);
}

// Gazes (pitch, yaw) on a grid of `step` degrees around `centre`, `pitch_steps`
// and `yaw_steps` each way, pitch-major.
std::vector<Eigen::Vector2d> GazeGrid(const Eigen::Vector2d& centre, int pitch_steps, int yaw_steps, double step) {
  std::vector<Eigen::Vector2d> gazes;
  for (int pitch = -pitch_steps; pitch <= pitch_steps; ++pitch) {
    for (int yaw = -yaw_steps; yaw <= yaw_steps; ++yaw) gazes.push_back(centre + step * Eigen::Vector2d(pitch, yaw));
  }
  return gazes;
}

}  // namespace

void ClampToBounds(Parameters& phi) {
  auto clamp_block = [&](Block block, double low, double high) {
    auto values = phi.values.segment(LayoutOf(block).offset, LayoutOf(block).size);
    values = values.cwiseMax(low).cwiseMin(high);
  };
  clamp_block(Block::kShape, -3, 3);
  clamp_block(Block::kTexture, -3, 3);
  clamp_block(Block::kIrisSize, 0.85, 1.08);
  clamp_block(Block::kPupilSize, 0.15, 0.7);  // 2 to 8 mm in an iris of 11.7 mm
  clamp_block(Block::kIrisColour, 0.0, 2.0);
  clamp_block(Block::kScleraTint, 0.0, 2.0);
  clamp_block(Block::kInterocular, 50, 76);
  clamp_block(Block::kEyelid, -kEyelidPitchBoundDeg, kEyelidPitchBoundDeg);
  clamp_block(Block::kEyelidClosure, -10, 45);
  clamp_block(Block::kAmbient, 0.0, 3.0);
  clamp_block(Block::kLightColour, 0.0, 3.0);
  clamp_block(Block::kLightDirection, -80, 80);
  phi.gaze_pitch() = std::clamp(phi.gaze_pitch(), -kGazePitchBoundDeg, kGazePitchBoundDeg);
  phi.gaze_yaw() = std::clamp(phi.gaze_yaw(), -50.0, 50.0);
  phi.vergence() = std::clamp(phi.vergence(), -4.0, 20.0);
}

double Fitter::StepSize(int index, const Parameters& phi, const Camera& camera) {
  const double depth = std::max(phi.translation().z(), 10.0);
  const double pixels_per_mm = camera.fx / depth;
  const double half_pixel_mm = 0.5 / pixels_per_mm;
  const Block block = Parameters::BlockOf(index);
  const int element = index - LayoutOf(block).offset;
  switch (block) {
    case Block::kShape: return 0.25;
    case Block::kIrisSize: return 0.015;
    case Block::kPupilSize: return 0.03;
    case Block::kRotation: return std::clamp(RadToDeg(half_pixel_mm / 25.0), 0.05, 2.0);  // 25 mm lever
    case Block::kTranslation: return element < 2 ? half_pixel_mm : half_pixel_mm * depth / 25.0;
    case Block::kInterocular: return 2 * half_pixel_mm;
    case Block::kGaze: return std::clamp(RadToDeg(half_pixel_mm / 10.75) * (element == 2 ? 2 : 1), 0.1, 3.0);
    case Block::kEyelid:
    case Block::kEyelidClosure: return std::clamp(RadToDeg(half_pixel_mm / 12.0), 0.2, 3.0);
    default: return 0.02;  // the appearance and light have exact derivatives; this is unused
  }
}

Fitter::Fitter(std::shared_ptr<const EyeRegionModel> model, FitOptions options, std::shared_ptr<ThreadPool> pool)
    : model_(std::move(model)),
      options_(options),
      pool_(pool ? std::move(pool) : std::make_shared<ThreadPool>()),
      landmarks_(*model_) {
  // One to hold Φ's render through a linearisation, one per thread for the rest.
  for (int i = 0; i <= pool_->size(); ++i) workspaces_.push_back(std::make_unique<EvaluationWorkspace>(model_));
}

std::vector<Fitter::Level> Fitter::Pyramid(const cv::Mat& image, const cv::Rect2d& region_d, const Camera& camera,
                                           const LandmarkModel& landmarks, const std::vector<Eigen::Vector2d>& targets,
                                           const std::vector<double>& weights, std::array<bool, 2> eyes,
                                           double scale) const {
  const cv::Rect region = cv::Rect(region_d) & cv::Rect(0, 0, image.cols, image.rows);
  std::vector<double> scales = {scale};
  if (options_.coarse_to_fine) scales.insert(scales.begin(), 0.5 * scale);
  std::vector<Level> levels;
  for (double s : scales) {
    const cv::Size size(std::max(8, static_cast<int>(std::lround(region.width * s))),
                        std::max(8, static_cast<int>(std::lround(region.height * s))));
    const Camera work = camera.Resampled(region.x, region.y, region.width, region.height, size.width, size.height);
    std::vector<Eigen::Vector2d> work_targets;
    const double sx = static_cast<double>(size.width) / region.width, sy = static_cast<double>(size.height) / region.height;
    for (const Eigen::Vector2d& p : targets) work_targets.push_back(Camera::ToResampled(p, region.x, region.y, sx, sy));
    Level level;
    level.problem = std::make_unique<FittingProblem>(model_, ObservedRegion(image, region, size), work, landmarks,
                                                     work_targets, weights, options_.weights, eyes);
    levels.push_back(std::move(level));
  }
  return levels;
}

FitResult Fitter::FitFace(const cv::Mat& image, const Camera& camera, const Face& face, const Parameters* start) {
  return FitFaceFrom(image, camera, face, start ? *start : InitializeFromLandmarks(face, camera, *model_),
                     start == nullptr);
}

FitResult Fitter::RefitFace(const cv::Mat& image, const Camera& camera, const Face& face, const Parameters& known) {
  // The light starts as it was too: a basic light under a held, fitted
  // texture can lose its directional part for good (its direction has no
  // gradient once its colour reaches zero).
  const ParameterMask light = MaskOf({Block::kAmbient, Block::kLightColour, Block::kLightDirection});
  Parameters phi = InitializeFromLandmarks(face, camera, *model_);
  for (int i = 0; i < kNumParameters; ++i) {
    if (!options_.free[i] || light[i]) phi.values[i] = known.values[i];
  }
  return FitFaceFrom(image, camera, face, phi, /*fresh=*/true);
}

FitResult Fitter::FitFaceFrom(const cv::Mat& image, const Camera& camera, const Face& face, Parameters phi,
                              bool fresh) {
  // The fitted region: the model's extent at the start, in the image.
  PosedModel posed;
  PoseWorkspace pose_work;
  model_->Pose(phi, posed, pose_work);
  const cv::Rect region = ModelBounds(posed, camera) & cv::Rect(0, 0, image.cols, image.rows);
  FitResult failed;
  failed.phi = phi;
  if (region.width < 16 || region.height < 8) {
    failed.note = "the eyes are too small or outside the image";
    return failed;
  }
  std::vector<Eigen::Vector2d> targets;
  std::vector<double> weights;
  for (const ModelLandmark& landmark : landmarks_.landmarks()) {
    targets.push_back(face.landmarks[landmark.dlib_index]);
    weights.push_back(GroupWeight(landmark.group, options_.weights));
  }
  const double scale = std::min(3.0, static_cast<double>(options_.work_width) / region.width);
  std::vector<Level> levels = Pyramid(image, region, camera, landmarks_, targets, weights, {true, true}, scale);
  FitResult result = Solve(levels, phi, options_.free, fresh);
  result.region = region;
  return result;
}

double EyePatchFraming::FramingYaw() const {
  if (!head_yaw_read) return head_yaw;
  return head_yaw * (1.0 - std::exp(-0.5 * std::pow(head_yaw / kReadingTrustDeg, 2)));
}

FitResult Fitter::FitEyePatch(const cv::Mat& crop, int eye, const EyePatchFraming& framing) {
  return FitEyePatchAt(crop, eye, 0.0, 0.0, framing);
}

Camera Fitter::EyePatchCamera(cv::Size crop) {
  // A long lens: the crop is a small part of a distant face.
  return {8.0 * crop.width, 8.0 * crop.width, 0.5 * (crop.width - 1), 0.5 * (crop.height - 1), crop.width, crop.height};
}

Parameters Fitter::EyePatchStart(cv::Size crop, int eye, const EyePatchFraming& framing) const {
  const Camera camera = EyePatchCamera(crop);
  Parameters phi;
  phi.interocular() = kAverageInterocularMm;
  const double spread = framing.corner_distance * crop.width;
  phi.block<Block::kTranslation>() = Eigen::Vector3d(0, 0, camera.fx * 27.0 / spread);
  // The eye's corners sit symmetrically about the crop's centre; the inner
  // corner is toward the nose (image left for the subject's left eye).
  const Eigen::Vector2d centre(camera.cx, camera.cy);
  const double inner_side = eye == kLeftEye ? -1.0 : 1.0;
  const double half = 0.5 * spread;
  const std::vector<CornerTarget> corners = {{eye, 0, centre + Eigen::Vector2d(inner_side * half, 0)},
                                             {eye, 1, centre - Eigen::Vector2d(inner_side * half, 0)}};
  phi.block<Block::kTranslation>() = FitTranslationToCorners(phi, *model_, camera, corners);
  const auto corner_spread = [&] {
    const auto model_corners = ModelEyeCorners(phi, *model_, eye);
    return std::abs(camera.Project(model_corners[0]).x() - camera.Project(model_corners[1]).x());
  };
  const double frontal_spread = corner_spread();
  const double framing_yaw = framing.FramingYaw();
  // A turned head foreshortens the eye, but the crop is scaled to it: the
  // head comes nearer until the corners are as far apart as facing the
  // camera. Then the eye is brought back to the crop's centre.
  for (int pass = 0; pass < 3; ++pass) {
    phi.block<Block::kRotation>() = Eigen::Vector3d(0, framing_yaw, 0);
    phi.block<Block::kTranslation>() *= corner_spread() / frontal_spread;
    phi.block<Block::kRotation>() = Eigen::Vector3d(0, framing.head_yaw, 0);
    const auto model_corners = ModelEyeCorners(phi, *model_, eye);
    const Eigen::Vector2d miss = 0.5 * (camera.Project(model_corners[0]) + camera.Project(model_corners[1])) - centre;
    const double depth = phi.translation().z();
    phi.block<Block::kTranslation>().head<2>() -= Eigen::Vector2d(miss.x() / camera.fx, miss.y() / camera.fy) * depth;
  }
  return phi;
}

FitResult Fitter::FitEyePatchAt(const cv::Mat& crop, int eye, double pitch, double yaw, const EyePatchFraming& framing,
                                 const AppearanceReading& appearance) {
  const Camera camera = EyePatchCamera(crop.size());
  Parameters phi = EyePatchStart(crop.size(), eye, framing);
  phi.gaze_pitch() = pitch;
  phi.gaze_yaw() = yaw;
  phi.eyelid_pitch() = pitch;
  const Eigen::Vector2d centre(camera.cx, camera.cy);

  // The crop's framing stands in for the landmarks: the mean of the eye's
  // landmarks sits at the crop's centre. Not the corners themselves: the
  // lids, and with them the landmarks, move with vertical gaze. It pulls only
  // at a landmark weight above 0, which EyePatchFitOptions leaves out.
  const LandmarkModel eye_centre = landmarks_.EyeCentre(eye);
  const std::vector<Eigen::Vector2d> targets = {centre};
  const std::vector<double> weights = {1.0};
  const double scale = std::min(4.0, static_cast<double>(options_.work_width) / crop.cols);
  std::array<bool, 2> eyes = {eye == kLeftEye, eye == kRightEye};
  std::vector<Level> levels =
      Pyramid(crop, cv::Rect2d(0, 0, crop.cols, crop.rows), camera, eye_centre, targets, weights, eyes, scale);
  for (Level& level : levels) level.problem->set_appearance(appearance);
  // One eye cannot tell the interocular distance or the vergence.
  ParameterMask free = options_.free;
  free[LayoutOf(Block::kInterocular).offset] = false;
  free[LayoutOf(Block::kGaze).offset + 2] = false;
  FitResult result = Solve(levels, phi, free, /*fresh=*/true);
  result.region = cv::Rect2d(0, 0, crop.cols, crop.rows);
  return result;
}

void Fitter::ExactColumns(const FittingProblem& problem, const Parameters& phi, const std::vector<int>& free,
                          const std::vector<std::pair<int, int>>& exact) {
  EvaluationWorkspace& work = main();
  std::vector<int> which;
  for (const auto& [column, k] : exact) which.push_back(k);
  work.renderer.ExactJacobian(phi, problem.camera(), work.buffers, which, exact_jacobian_);
  const std::vector<int>& domain = problem.domain();
  pixel_scales_.resize(domain.size());
  for (std::size_t d = 0; d < domain.size(); ++d) pixel_scales_[d] = problem.PixelScale(work, domain[d]);
  const int rows = problem.num_residuals();
  const int texture_prior_row = rows - FittingProblem::kPoseResiduals - kNumTextureModes;
  for (std::size_t n = 0; n < exact.size(); ++n) {
    const int column = exact[n].first;
    auto out = jacobian_.col(column);
    out.setZero();
    const auto derivatives = exact_jacobian_.col(static_cast<Eigen::Index>(n));
    for (std::size_t d = 0; d < domain.size(); ++d) {
      const int i = work.foreground_index[domain[d]];
      if (i < 0) continue;
      for (int c = 0; c < 3; ++c) out[3 * static_cast<Eigen::Index>(d) + c] = derivatives[3 * i + c] * pixel_scales_[d];
    }
    const int parameter = free[column];
    const int texture = parameter - LayoutOf(Block::kTexture).offset;
    if (texture >= 0 && texture < kNumTextureModes) {
      out[texture_prior_row + texture] = static_cast<float>(std::sqrt(problem.weights().texture));
    }
  }
}

double Fitter::Linearize(FittingProblem& problem, const Parameters& phi, const std::vector<int>& free,
                         Eigen::MatrixXd& normal, Eigen::VectorXd& gradient) {
  const int rows = problem.num_residuals();
  const int columns = static_cast<int>(free.size());
  jacobian_.resize(rows, columns);
  const EnergyTerms terms = problem.Evaluate(phi, main(), &residuals_);
  std::vector<int> numeric;
  std::vector<std::pair<int, int>> exact;  // (column, index in Renderer::ExactParameters)
  const std::vector<int>& exact_parameters = Renderer::ExactParameters();
  for (int c = 0; c < columns; ++c) {
    const auto found = std::find(exact_parameters.begin(), exact_parameters.end(), free[c]);
    if (found == exact_parameters.end()) {
      numeric.push_back(c);
    } else {
      exact.emplace_back(c, static_cast<int>(found - exact_parameters.begin()));
    }
  }
  // The exact columns come from Φ's render in the main workspace, so they are
  // one task beside the central differences (two renders per parameter),
  // which render in the threads' own workspaces.
  const int exact_tasks = exact.empty() ? 0 : 1;
  pool_->ParallelFor(static_cast<int>(numeric.size()) + exact_tasks, [&](int task, int worker) {
    if (task < exact_tasks) {
      ExactColumns(problem, phi, free, exact);
      return;
    }
    EvaluationWorkspace& work = scratch(worker);
    const int column = numeric[task - exact_tasks];
    const int index = free[column];
    const double h = StepSize(index, phi, problem.camera());
    Parameters up = phi, down = phi;
    up[index] += h;
    down[index] -= h;
    problem.Evaluate(up, work, &work.plus);
    problem.Evaluate(down, work, &work.minus);
    jacobian_.col(column) = (work.plus - work.minus) / static_cast<float>(2 * h);
  });
  NormalEquations(normal, gradient);
  return terms.total();
}

void Fitter::NormalEquations(Eigen::MatrixXd& normal, Eigen::VectorXd& gradient) const {
  // The Gram matrix of [J r] holds JᵀJ and, in its last row, Jᵀr. One thread:
  // spread over two, the sums took as long (the columns were written by both).
  const Eigen::Index columns = jacobian_.cols();
  std::vector<const float*> data;
  for (Eigen::Index c = 0; c < columns; ++c) data.push_back(jacobian_.col(c).data());
  data.push_back(residuals_.data());
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(columns + 1, columns + 1);
  AddGramLowerTriangle(data, jacobian_.rows(), gram);
  normal = gram.topLeftCorner(columns, columns).selfadjointView<Eigen::Lower>();
  gradient = gram.row(columns).head(columns).transpose();
}

// Iterations of annealed Gauss-Newton on one pyramid level, from Φ; counts
// the fit's iterations in `progress` (for the annealing schedule). Returns
// whether it stopped because E stopped falling.
bool Fitter::RunLevel(FittingProblem& problem, int level, int budget, const std::vector<int>& free,
                      const Eigen::Vector2d* search_centre, Parameters& phi, int& iteration, std::vector<FitIteration>* history) {
  const double base_landmarks = options_.weights.landmarks;
  int stalled = 0;
  for (int local = 0; local < budget; ++local, ++iteration) {
    const double progress = options_.max_iterations > 1 ? static_cast<double>(iteration) / (options_.max_iterations - 1) : 1.0;
    problem.weights().landmarks = base_landmarks * (1.0 - (1.0 - options_.landmark_final) * progress);
    const EnergyTerms current = problem.Evaluate(phi, main(), nullptr);
    problem.SetDomain(main().buffers, kDomainMargin);
    if (history != nullptr && history->empty()) history->push_back({level, current, phi, 0.0});

    Eigen::MatrixXd normal;
    Eigen::VectorXd gradient;
    const double energy = Linearize(problem, phi, free, normal, gradient);
    Eigen::MatrixXd damped = normal;
    damped.diagonal() += kDamping * normal.diagonal() + Eigen::VectorXd::Constant(normal.rows(), 1e-12);
    const Eigen::VectorXd step = -damped.ldlt().solve(gradient);
    if (!step.allFinite()) return true;

    // Annealed step, halved until the energy falls.
    double eta = std::min(1.0, options_.first_step + options_.step_growth * iteration);
    bool accepted = false;
    for (int attempt = 0; attempt <= kMaxBacktracks && !accepted; ++attempt, eta *= 0.5) {
      Parameters trial = phi;
      for (std::size_t k = 0; k < free.size(); ++k) trial[free[k]] += eta * step[static_cast<Eigen::Index>(k)];
      ClampToBounds(trial);
      const EnergyTerms terms = problem.Evaluate(trial, main(), nullptr);
      if (terms.foreground > 0 && terms.total() < energy) {
        const double decrease = (energy - terms.total()) / std::max(energy, 1e-12);
        phi = trial;
        accepted = true;
        stalled = decrease < options_.tolerance ? stalled + 1 : 0;
        if (history != nullptr) history->push_back({level, terms, phi, eta});
      }
    }
    if (search_centre != nullptr && local == 0) {
      phi = SearchGaze(problem, phi, *search_centre);
      accepted = true;
      stalled = 0;
    }
    if (!accepted || stalled >= 2) {
      ++iteration;
      problem.weights().landmarks = base_landmarks;
      return true;
    }
  }
  problem.weights().landmarks = base_landmarks;
  return false;
}

FitResult Fitter::Solve(std::vector<Level>& levels, Parameters phi, const ParameterMask& mask, bool fresh) {
  std::vector<int> free;
  for (int i = 0; i < kNumParameters; ++i) {
    if (mask[i]) free.push_back(i);
  }
  FitResult result;
  ClampToBounds(phi);
  const int num_levels = static_cast<int>(levels.size());
  std::vector<FitIteration>* history = options_.record_history ? &result.history : nullptr;
  int iteration = 0;
  int first_level = 0;
  // A fresh fit's gaze search is centred on looking into the lens as seen
  // from the starting head pose (the landmarks', or the one given for an eye
  // patch): people in photos mostly look near the camera, and from a turned
  // head that is a turned eye. Not from the pose after an iteration, which
  // one eye alone hardly tells.
  const Eigen::Vector2d lens = LookingIntoTheLens(phi, levels[0].problem->eyes());
  const Eigen::Vector2d* search_centre = fresh && options_.gaze_search ? &lens : nullptr;
  // A fresh fit starts the coarsest level from several gaze pitches and goes
  // on from the lowest energy: pitch has more than one basin.
  if (fresh && num_levels > 1 && options_.pitch_starts.size() > 1) {
    const int budget = std::max(1, options_.max_iterations / 3);
    double best = std::numeric_limits<double>::infinity();
    Parameters best_phi = phi;
    std::vector<FitIteration> best_history;
    int best_iteration = 0;
    for (double pitch : options_.pitch_starts) {
      Parameters start = phi;
      start.eyelid_pitch() += pitch - start.gaze_pitch();
      start.gaze_pitch() = pitch;
      ClampToBounds(start);
      std::vector<FitIteration> start_history;
      int start_iteration = 0;
      RunLevel(*levels[0].problem, 0, budget, free, search_centre, start, start_iteration,
               history ? &start_history : nullptr);
      const double energy = levels[0].problem->Evaluate(start, main(), nullptr).total();
      if (energy < best) best = energy, best_phi = start, best_history = start_history, best_iteration = start_iteration;
    }
    phi = best_phi;
    iteration = best_iteration;
    if (history) *history = best_history;
    first_level = 1;
  }
  const bool gaze_free = mask[LayoutOf(Block::kGaze).offset];
  if (!fresh && gaze_free && options_.jump_search_step > 0) phi = BestGaze(*levels[0].problem, phi, JumpGazes(phi, lens));
  for (int l = first_level; l < num_levels; ++l) {
    const int budget = l + 1 < num_levels ? std::max(1, options_.max_iterations / 3) : options_.max_iterations - iteration;
    result.converged = RunLevel(*levels[l].problem, l, budget, free, l == 0 ? search_centre : nullptr, phi, iteration, history);
  }
  result.iterations = iteration;
  FittingProblem& finest = *levels.back().problem;
  result.phi = phi;
  result.terms = finest.Evaluate(phi, main(), nullptr);
  result.work_camera = finest.camera();
  Assess(result, finest);
  return result;
}

Parameters Fitter::SearchGaze(FittingProblem& problem, const Parameters& phi, const Eigen::Vector2d& centre) {
  const double step = options_.gaze_search_step;
  const Eigen::Vector2d grid_centre = (centre / step).array().round() * step;
  const int pitch_steps = static_cast<int>(std::floor(options_.gaze_search_pitch / step + 1e-9));
  const int yaw_steps = static_cast<int>(std::floor(options_.gaze_search_yaw / step + 1e-9));
  return BestGaze(problem, phi, GazeGrid(grid_centre, pitch_steps, yaw_steps, step));
}

Parameters Fitter::BestGaze(FittingProblem& problem, const Parameters& phi, const std::vector<Eigen::Vector2d>& gazes) {
  std::vector<Parameters> candidates;
  for (const Eigen::Vector2d& gaze : gazes) {
    Parameters candidate = phi;
    candidate.gaze_pitch() = gaze.x();
    candidate.gaze_yaw() = gaze.y();
    // The lids stay: moved with the gaze they could close over a
    // hard-to-explain iris, which would look like a good fit.
    ClampToBounds(candidate);
    candidates.push_back(candidate);
  }
  candidates.push_back(phi);
  std::vector<double> energies(candidates.size());
  pool_->ParallelFor(static_cast<int>(candidates.size()), [&](int i, int worker) {
    energies[i] = problem.Evaluate(candidates[i], scratch(worker), nullptr).total();
  });
  return candidates[std::min_element(energies.begin(), energies.end()) - energies.begin()];
}

std::vector<Eigen::Vector2d> Fitter::JumpGazes(const Parameters& phi, const Eigen::Vector2d& lens) const {
  const double step = options_.jump_search_step;
  const Eigen::Vector2d start(phi.gaze_pitch(), phi.gaze_yaw());
  std::vector<Eigen::Vector2d> gazes;
  for (const Eigen::Vector2d& gaze : GazeGrid(start, 1, 1, step)) {
    if (gaze != start) gazes.push_back(gaze);  // BestGaze tries Φ itself
  }
  const std::vector<Eigen::Vector2d> around_lens = GazeGrid(lens, 1, 2, step);
  gazes.insert(gazes.end(), around_lens.begin(), around_lens.end());
  return gazes;
}

void Fitter::Assess(FitResult& result, const FittingProblem& problem) const {
  // Landmark agreement on the lids and corners, relative to the eye's width.
  const auto& targets = problem.target_landmarks();
  const auto& landmarks = problem.landmark_model().landmarks();
  std::vector<Eigen::Vector2d> projected;
  problem.landmark_model().Project(main().renderer.posed(), problem.camera(), projected);
  double squared = 0, width = 0;
  int count = 0;
  for (std::size_t k = 0; k < landmarks.size() && !targets.empty(); ++k) {
    if (landmarks[k].group != LandmarkGroup::kEyelid) continue;
    squared += (projected[k] - targets[k]).squaredNorm();
    ++count;
  }
  for (int eye = 0; eye < 2; ++eye) {
    if (!problem.eyes()[eye]) continue;
    const auto corners = ModelEyeCorners(result.phi, *model_, eye);
    width = std::max(width, (problem.camera().Project(corners[0]) - problem.camera().Project(corners[1])).norm());
  }
  result.landmark_error = count > 0 && width > 0 ? std::sqrt(squared / count) / width : std::numeric_limits<double>::quiet_NaN();
  const double rms_colour = std::sqrt(result.terms.image);
  if (result.terms.foreground < 100) {
    result.note = "the model covers almost no pixels";
  } else if (rms_colour > 0.2) {
    result.note = "the rendered eyes do not match the photo";
  } else if (result.landmark_error > 0.15) {
    result.note = "the model's lids do not follow the tracked landmarks";
  } else {
    result.good = true;
  }
}

}  // namespace gazedirector
