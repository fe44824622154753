#include "gazedirector/video/gaze_tracker.h"

#include <algorithm>

namespace gazedirector {

FitOptions WarmFitOptions() {
  FitOptions options;
  options.max_iterations = 5;
  options.coarse_to_fine = false;
  options.jump_search_step = 10;
  options.first_step = 0.8;
  options.landmark_final = 1.0;
  return options;
}

FitOptions GazeTrackerOptions::SettledWarm() const {
  FitOptions settled = warm;
  for (Block block : {Block::kShape, Block::kTexture, Block::kIrisSize, Block::kIrisColour, Block::kScleraTint,
                      Block::kInterocular}) {
    for (int i = 0; i < LayoutOf(block).size; ++i) settled.free[LayoutOf(block).offset + i] = false;
  }
  return settled;
}

GazeTracker::GazeTracker(std::shared_ptr<const EyeRegionModel> model, std::shared_ptr<const LandmarkDetector> landmarks,
                         MeanFace mean_face, GazeTrackerOptions options, std::shared_ptr<ThreadPool> pool,
                         bool largest_only)
    : model_(model),
      options_(options),
      faces_(std::move(landmarks), mean_face, [&] {
        FaceTrackerOptions face_options;
        face_options.largest_only = largest_only;
        return face_options;
      }()),
      fresh_(model, options.fresh, pool ? pool : (pool = std::make_shared<ThreadPool>())),
      warm_(model, options.warm, pool) {}

void GazeTracker::Reset() {
  faces_.Reset();
  histories_.clear();
}

std::vector<FaceFit> GazeTracker::ProcessImage(const cv::Mat& image, const Camera& camera) {
  std::vector<FaceFit> fits;
  for (const Face& face : faces_.DetectFaces(image, camera)) fits.push_back(Fit(image, camera, face, nullptr));
  return fits;
}

std::vector<FaceFit> GazeTracker::ProcessFrame(const cv::Mat& frame, double timestamp_s, const Camera& camera) {
  std::vector<FaceFit> fits;
  std::map<int, History> still_here;
  for (const Face& face : faces_.TrackFrame(frame, timestamp_s, camera)) {
    History& history = histories_[face.id];
    fits.push_back(Fit(frame, camera, face, &history));
    still_here[face.id] = history;
  }
  histories_ = std::move(still_here);  // faces that left are forgotten
  return fits;
}

FaceFit GazeTracker::Fit(const cv::Mat& image, const Camera& camera, const Face& face, History* history) {
  FaceFit result;
  result.face = face;
  if (history != nullptr && history->fits > 0) {
    // Warm start; settled parameters held.
    warm_.options().free = history->fits >= options_.settle_frames ? options_.SettledWarm().free : options_.warm.free;
    result.fit = warm_.FitFace(image, camera, face, &history->phi);
    result.warm = true;
    const bool degraded = !result.fit.good || (history->typical_energy > 0 &&
                                               result.fit.terms.total() > options_.refit_ratio * history->typical_energy);
    if (degraded) {
      FitResult fresh = fresh_.FitFace(image, camera, face);
      if (fresh.terms.total() < result.fit.terms.total()) {
        result.fit = fresh;
        result.warm = false;
      }
    }
  } else {
    result.fit = fresh_.FitFace(image, camera, face);
  }
  if (history != nullptr) {
    history->phi = result.fit.phi;
    ++history->fits;
    if (result.fit.good) {
      const double energy = result.fit.terms.total();
      history->typical_energy = history->typical_energy > 0 ? 0.8 * history->typical_energy + 0.2 * energy : energy;
    }
  }
  return result;
}

}  // namespace gazedirector
