#include "gazedirector/fit/fitting_problem.h"

#include <array>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace gazedirector {

FittingProblem::FittingProblem(std::shared_ptr<const EyeRegionModel> model, const cv::Mat& observed_rgb,
                               const Camera& camera, const LandmarkModel& landmark_model,
                               std::vector<Eigen::Vector2d> target_landmarks, std::vector<double> landmark_weights,
                               const EnergyWeights& weights, std::array<bool, 2> eyes)
    : model_(std::move(model)),
      observed_(observed_rgb),
      camera_(camera),
      landmark_model_(landmark_model),
      targets_(std::move(target_landmarks)),
      landmark_weights_(std::move(landmark_weights)),
      weights_(weights),
      eyes_(eyes) {
  CV_Assert(observed_.type() == CV_32FC3 && observed_.cols == camera.width && observed_.rows == camera.height);
  CV_Assert(targets_.empty() || targets_.size() == landmark_model_.landmarks().size());
  CV_Assert(landmark_weights_.size() == targets_.size());
}

void FittingProblem::SetDomain(const RenderBuffers& current, int margin) {
  cv::Mat mask = current.MaskImage();
  if (margin > 0) {
    cv::dilate(mask, mask, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * margin + 1, 2 * margin + 1)));
  }
  domain_.clear();
  for (int i = 0; i < mask.rows * mask.cols; ++i) {
    if (mask.data[i]) domain_.push_back(i);
  }
}

int FittingProblem::num_residuals() const {
  constexpr int kPupilPrior = 1;
  return num_image_residuals() + 2 * static_cast<int>(targets_.size()) + kNumShapeModes + kPupilPrior +
         kNumTextureModes + kPoseResiduals;
}

namespace {

// The shape prior's pupil: about 4 mm across in an iris of 11.7 mm (2 to 8 mm
// from bright light to the dark). Where the pupil does not show (a dark iris,
// a narrow opening) it stays near this.
constexpr double kTypicalPupilSize = 0.35;
constexpr double kPupilSizeSd = 0.15;

// What a pixel's colour difference is multiplied by in the residuals: the
// robust truncation caps its squared error at `truncation`.
float TruncatedScale(float squared, float truncation, float inverse_root_area) {
  return squared > truncation ? inverse_root_area * std::sqrt(truncation / squared) : inverse_root_area;
}

// The sum over the foreground of the truncated squared colour errors, eyeball
// pixels weighted. Eight independent sums (in double: the line search compares
// energies that differ in their sixth digit) let the loop run in vector lanes.
double ImageError(const RenderBuffers& buffers, const float* observed, float truncation, float eyeball_weight) {
  constexpr int kLanes = 8;
  const int count = static_cast<int>(buffers.foreground.size());
  const int* foreground = buffers.foreground.data();
  const int32_t* triangle = buffers.visibility.triangle_data();
  const int32_t first_eyeball = buffers.part_offsets[kLeftEyeball];
  const float* red = buffers.colour.data();
  const float* green = red + buffers.colour.rows();
  const float* blue = green + buffers.colour.rows();
  auto error = [&](int i) {
    const int pixel = foreground[i];
    const float* rgb = observed + 3 * static_cast<std::ptrdiff_t>(pixel);
    const float dr = red[i] - rgb[0], dg = green[i] - rgb[1], db = blue[i] - rgb[2];
    const float weight = triangle[pixel] >= first_eyeball ? eyeball_weight : 1.0f;
    return weight * std::min(dr * dr + dg * dg + db * db, truncation);
  };
  std::array<double, kLanes> sums{};
  int i = 0;
  for (; i + kLanes <= count; i += kLanes) {
    for (int k = 0; k < kLanes; ++k) sums[k] += error(i + k);
  }
  for (; i < count; ++i) sums[0] += error(i);
  double total = 0;
  for (double sum : sums) total += sum;
  return total;
}

// The sum of squares of a parameter block, in a plain loop, so the same in
// every build. (With AVX-512, GCC 12 also warns inside its own headers where
// Eigen reduces these fixed-size blocks.)
template <typename Block>
double SumOfSquares(const Block& block) {
  double sum = 0;
  for (int i = 0; i < block.size(); ++i) sum += block[i] * block[i];
  return sum;
}

}  // namespace

float FittingProblem::PixelScale(const EvaluationWorkspace& work, int pixel) const {
  const int row = work.foreground_index[pixel];
  if (row < 0) return 0.0f;
  const float inverse_root_area = 1.0f / std::sqrt(static_cast<float>(work.buffers.foreground.size()));
  const cv::Vec3f observed = observed_.at<cv::Vec3f>(pixel / camera_.width, pixel % camera_.width);
  float squared = 0;
  for (int c = 0; c < 3; ++c) squared += std::pow(work.buffers.colour(row, c) - observed[c], 2.0f);
  const float truncation = static_cast<float>(weights_.truncation);
  const float scale = TruncatedScale(squared, truncation, inverse_root_area);
  const bool eyeball = work.buffers.visibility.triangle(pixel) >= work.buffers.part_offsets[kLeftEyeball];
  return eyeball ? scale * static_cast<float>(std::sqrt(weights_.eyeball_pixels)) : scale;
}

void EvaluationWorkspace::Render(const Parameters& phi, const Camera& camera, std::array<bool, 2> eyes) {
  if (holds_render_ && eyes == rendered_eyes_ && camera == rendered_camera_ && phi.values == rendered_phi_.values) return;
  renderer.set_eyes(eyes[0], eyes[1]);
  renderer.Render(phi, camera, buffers);
  holds_render_ = true;
  rendered_phi_ = phi, rendered_camera_ = camera, rendered_eyes_ = eyes;
}

EnergyTerms FittingProblem::Evaluate(const Parameters& phi, EvaluationWorkspace& work, Eigen::VectorXf* residuals) const {
  work.Render(phi, camera_, eyes_);
  const RenderBuffers& buffers = work.buffers;
  EnergyTerms terms;
  terms.foreground = static_cast<int>(buffers.foreground.size());
  // An empty render explains nothing: the worst energy.
  const double area = std::max(terms.foreground, 1);
  const float truncation = static_cast<float>(weights_.truncation);

  const float* observed = observed_.ptr<float>();
  const int first_eyeball = buffers.part_offsets[kLeftEyeball];
  const float eyeball_weight = static_cast<float>(weights_.eyeball_pixels);
  terms.image = terms.foreground > 0 ? ImageError(buffers, observed, truncation, eyeball_weight) / area : weights_.truncation;

  const double landmark_scale = weights_.landmarks / area;
  if (!targets_.empty()) {
    landmark_model_.Project(work.renderer.posed(), camera_, work.landmarks);
    for (std::size_t k = 0; k < targets_.size(); ++k) {
      terms.landmarks += landmark_scale * landmark_weights_[k] * (work.landmarks[k] - targets_[k]).squaredNorm();
    }
  }
  const double pupil_sd = (phi.pupil_size() - kTypicalPupilSize) / kPupilSizeSd;
  terms.stats = weights_.shape * (SumOfSquares(phi.shape()) + pupil_sd * pupil_sd) +
                weights_.texture * SumOfSquares(phi.texture());
  terms.pose = weights_.pose * std::pow(phi.eyelid_pitch() - phi.gaze_pitch(), 2) +
               weights_.vergence * phi.vergence() * phi.vergence() +
               weights_.closure * phi.eyelid_closure() * phi.eyelid_closure();
  // Eye patches fit one eye with the vergence held at 0, so its yaw is the gaze yaw.
  const double pitch_miss = std::isnan(appearance_.pitch) ? 0.0 : phi.gaze_pitch() - appearance_.pitch;
  const double yaw_miss = std::isnan(appearance_.yaw) ? 0.0 : phi.gaze_yaw() - appearance_.yaw;
  const double yaw_weight = weights_.AppearanceYaw(appearance_.frontal);
  terms.pose += weights_.appearance_pitch * pitch_miss * pitch_miss + yaw_weight * yaw_miss * yaw_miss;

  if (residuals == nullptr) return terms;
  work.foreground_index.assign(static_cast<std::size_t>(camera_.width) * camera_.height, -1);
  for (int i = 0; i < terms.foreground; ++i) work.foreground_index[buffers.foreground[i]] = i;
  Eigen::VectorXf& r = *residuals;
  r.resize(num_residuals());
  const float inverse_root_area = static_cast<float>(1.0 / std::sqrt(area));
  const float eyeball_scale = std::sqrt(eyeball_weight);
  const int32_t* triangle = buffers.visibility.triangle_data();
  const int* index = work.foreground_index.data();
  int row = 0;
  for (int pixel : domain_) {
    const int i = index[pixel];
    if (i < 0) {
      r.segment<3>(row).setZero();
    } else {
      Eigen::Vector3f difference;
      for (int c = 0; c < 3; ++c) difference[c] = buffers.colour(i, c) - observed[3 * pixel + c];
      const float squared = difference.squaredNorm();
      float scale = TruncatedScale(squared, truncation, inverse_root_area);
      if (triangle[pixel] >= first_eyeball) scale *= eyeball_scale;
      r.segment<3>(row) = difference * scale;
    }
    row += 3;
  }
  for (std::size_t k = 0; k < targets_.size(); ++k) {
    const double scale = std::sqrt(landmark_scale * landmark_weights_[k]);
    r.segment<2>(row) = ((work.landmarks[k] - targets_[k]) * scale).cast<float>();
    row += 2;
  }
  r.segment<kNumShapeModes>(row) = (std::sqrt(weights_.shape) * phi.shape()).cast<float>();
  row += kNumShapeModes;
  r[row++] = static_cast<float>(std::sqrt(weights_.shape) * pupil_sd);
  r.segment<kNumTextureModes>(row) = (std::sqrt(weights_.texture) * phi.texture()).cast<float>();
  row += kNumTextureModes;
  r[row] = static_cast<float>(std::sqrt(weights_.pose) * (phi.eyelid_pitch() - phi.gaze_pitch()));
  r[row + 1] = static_cast<float>(std::sqrt(weights_.vergence) * phi.vergence());
  r[row + 2] = static_cast<float>(std::sqrt(weights_.closure) * phi.eyelid_closure());
  r[row + 3] = static_cast<float>(std::sqrt(weights_.appearance_pitch) * pitch_miss);
  r[row + 4] = static_cast<float>(std::sqrt(yaw_weight) * yaw_miss);
  return terms;
}

}  // namespace gazedirector
