#include "gazedirector/video/gaze_tracker.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <spdlog/spdlog.h>

#include "gazedirector/fit/iris_alignment.h"

namespace gazedirector {
namespace {

// The parameters that settle in a video: shape, texture (skin, iris colour,
// sclera tint), iris and pupil size and interocular distance.
constexpr std::initializer_list<Block> kSettledBlocks = {Block::kShape,      Block::kTexture,    Block::kIrisSize,
                                                          Block::kPupilSize,  Block::kIrisColour, Block::kScleraTint,
                                                          Block::kInterocular};

// Holds them.
FitOptions HoldSettled(FitOptions options) {
  Hold(options.free, kSettledBlocks);
  return options;
}

// `phi` with the settled parameters of `settled`.
Parameters WithSettled(Parameters phi, const Parameters& settled) {
  for (Block block : kSettledBlocks) {
    const BlockLayout& layout = LayoutOf(block);
    phi.values.segment(layout.offset, layout.size) = settled.values.segment(layout.offset, layout.size);
  }
  return phi;
}

// Whether the fit has run into the lids' bound, or its gaze pitch beyond
// where the lids can follow: a wrong minimum (eyes rolled up under the lids),
// or a shape that cannot follow the face's expression.
bool AtALimit(const Parameters& phi) {
  constexpr double kLimit = kEyelidPitchBoundDeg - 0.1;
  return std::abs(phi.eyelid_pitch()) >= kLimit || std::abs(phi.gaze_pitch()) >= kLimit;
}

// A fit the fitter flags as bad, or one at a limit.
bool Stuck(const FitResult& fit) { return !fit.good || AtALimit(fit.phi); }

FitOptions WithVergenceFree(FitOptions options, bool free) {
  if (free) options.weights.vergence = 0;
  return options;
}

}  // namespace

FitOptions WarmFitOptions() {
  FitOptions options;
  options.max_iterations = 5;
  options.coarse_to_fine = false;
  options.jump_search_step = 10;
  options.first_step = 0.8;
  options.landmark_final = 1.0;
  return options;
}

FitOptions GazeTrackerOptions::SettledWarm() const { return HoldSettled(warm); }

GazeTracker::GazeTracker(std::shared_ptr<const EyeRegionModel> model, std::shared_ptr<const LandmarkDetector> landmarks,
                         MeanFace mean_face, GazeTrackerOptions options, std::shared_ptr<ThreadPool> pool,
                         bool largest_only)
    : model_(model),
      options_(options),
      faces_(std::move(landmarks), mean_face, FaceOptions(largest_only, options.head_pose)),
      fresh_(model, options.fresh, pool ? pool : (pool = std::make_shared<ThreadPool>())),
      warm_(model, options.warm, pool),
      renderer_(model) {}

FaceTrackerOptions GazeTracker::FaceOptions(bool largest_only, HeadPoseMethod head_pose) {
  FaceTrackerOptions options;
  options.largest_only = largest_only;
  options.head_pose = head_pose;
  return options;
}

void GazeTracker::Reset() {
  faces_.Reset();
  histories_.clear();
}

std::vector<FaceFit> GazeTracker::ProcessImage(const cv::Mat& image, const Camera& camera) {
  return FitImageFaces(image, camera, faces_.DetectFaces(image, camera));
}

std::vector<FaceFit> GazeTracker::FitImageFaces(const cv::Mat& image, const Camera& camera,
                                                const std::vector<Face>& faces) {
  std::vector<FaceFit> fits;
  for (const Face& face : faces) fits.push_back(Fit(image, camera, face, nullptr, 0.0));
  return fits;
}

GazeTracker::FreshFit GazeTracker::FitFresh(const cv::Mat& image, const Camera& camera, const Face& face,
                                            FitOptions options, bool free_vergence) {
  fresh_.options() = WithVergenceFree(options, free_vergence);
  FreshFit fit{fresh_.FitFace(image, camera, face), free_vergence};
  const double limit = options_.free_vergence_iris_offset;
  if (free_vergence || limit <= 0 || !fit.fit.good) return fit;
  const double offset = WorstIrisMisalignment(image, camera, fit.fit.phi, {true, true}, renderer_);
  if (offset <= limit) return fit;
  fresh_.options() = WithVergenceFree(options, true);
  FitResult free = fresh_.FitFace(image, camera, face);
  const double free_offset = WorstIrisMisalignment(image, camera, free.phi, {true, true}, renderer_);
  spdlog::debug("face {}: an iris {:.2f} radii off its eye; with the vergence free {:.2f} (vergence {:.1f} deg, "
                "image energy {:.5f} against {:.5f})",
                face.id, offset, free_offset, free.phi.vergence(), free.terms.image, fit.fit.terms.image);
  // Freed, eyes that only look noisy drift apart (diverging) as readily as
  // together: only a fit that converges answers the question.
  const bool better = free.good && free.phi.vergence() > 0 && free_offset <= limit && free_offset < offset &&
                      free.terms.image <= fit.fit.terms.image;
  if (!better) return fit;
  return {std::move(free), true};
}

std::vector<FaceFit> GazeTracker::ProcessFrame(const cv::Mat& frame, double timestamp_s, const Camera& camera) {
  return FitFaces(frame, timestamp_s, camera, TrackFaces(frame, timestamp_s, camera));
}

std::vector<Face> GazeTracker::TrackFaces(const cv::Mat& frame, double timestamp_s, const Camera& camera) {
  return faces_.TrackFrame(frame, timestamp_s, camera);
}

std::vector<FaceFit> GazeTracker::FitFaces(const cv::Mat& frame, double timestamp_s, const Camera& camera,
                                           const std::vector<Face>& faces) {
  std::vector<FaceFit> fits;
  std::map<int, History> still_here;
  for (const Face& face : faces) {
    History& history = histories_[face.id];
    fits.push_back(Fit(frame, camera, face, &history, timestamp_s));
    still_here[face.id] = history;
  }
  histories_ = std::move(still_here);  // faces that left are forgotten
  return fits;
}

bool GazeTracker::InABlink(double opening, double timestamp_s, History& history) const {
  if (opening >= options_.closed_eye_fraction) {
    history.narrow_since_s = -1;
    return false;
  }
  if (history.narrow_since_s < 0) history.narrow_since_s = timestamp_s;
  return timestamp_s - history.narrow_since_s <= options_.max_blink_s;
}

FaceFit GazeTracker::Fit(const cv::Mat& image, const Camera& camera, const Face& face, History* history,
                         double timestamp_s) {
  FaceFit result;
  result.face = face;
  // How open the eyes are, as a fraction of how open they usually are.
  const double opening = history != nullptr ? history->opening.Update(SmallerEyeAspectRatio(face.landmarks)) : 1.0;
  result.eyes_closed = history != nullptr && InABlink(opening, timestamp_s, *history);
  if (history != nullptr && history->fits > 0) {
    const bool settled = history->fits >= options_.settle_frames;
    FitOptions options = WithVergenceFree(settled ? options_.SettledWarm() : options_.warm, history->free_vergence);
    Parameters start = history->phi;
    if (result.eyes_closed) {
      Hold(options.free, {Block::kGaze});
      // The lids start as far closed as the landmarks say: closing from wide
      // open, Gauss-Newton would rather look down than close.
      start.eyelid_closure() = std::max(start.eyelid_closure(), options_.closed_lid_deg * (1.0 - opening));
    }
    warm_.options() = options;
    result.fit = warm_.FitFace(image, camera, face, &start);
    result.warm = true;
    // Keeps a refit when it explains the frame better.
    auto keep_if_better = [&result, history](FitResult refit, bool free_vergence) {
      if (refit.terms.total() >= result.fit.terms.total()) return;
      result.fit = std::move(refit);
      result.warm = false;
      history->free_vergence = free_vergence;
    };
    const Parameters usual_start = settled ? WithSettled(start, history->settled) : start;
    if (usual_start.values != start.values) {
      // The last frames needed a shape of their own (see below): the usual
      // one is tried again and kept whenever it explains the frame as well.
      FitResult usual = warm_.FitFace(image, camera, face, &usual_start);
      if (usual.terms.total() <= result.fit.terms.total()) result.fit = std::move(usual);
    }
    // A blink's energy is unusual, and a fresh fit cannot see its gaze either.
    const bool degraded = !result.eyes_closed &&
                          (Stuck(result.fit) ||
                           (history->typical_energy > 0 &&
                            result.fit.terms.total() > options_.refit_ratio * history->typical_energy));
    if (degraded) {
      // A settled face keeps its shape and texture: refits happen on unusual
      // frames (a half-closed eye, a fast turn), the worst to learn them from.
      // (Not in a blink, so `start` is the last fit and usual_start its settled version.)
      if (settled) {
        fresh_.options() = WithVergenceFree(HoldSettled(options_.fresh), history->free_vergence);
        keep_if_better(fresh_.RefitFace(image, camera, face, usual_start), history->free_vergence);
      } else {
        FreshFit refit = FitFresh(image, camera, face, options_.fresh, history->free_vergence);
        keep_if_better(std::move(refit.fit), refit.free_vergence);
      }
      if (settled && Stuck(result.fit)) {
        // An expression the settled shape cannot follow (eyes opened wide
        // while looking aside): this frame, and the next ones while it
        // explains them better, get a shape and texture of their own.
        FreshFit refit = FitFresh(image, camera, face, options_.fresh, history->free_vergence);
        keep_if_better(std::move(refit.fit), refit.free_vergence);
      }
    }
  } else {
    FreshFit fresh = FitFresh(image, camera, face, options_.fresh, false);
    result.fit = std::move(fresh.fit);
    if (history != nullptr) history->free_vergence = fresh.free_vergence;
  }
  if (history != nullptr) {
    history->phi = result.fit.phi;
    if (++history->fits == options_.settle_frames) history->settled = result.fit.phi;
    if (result.fit.good && !result.eyes_closed) {
      const double energy = result.fit.terms.total();
      history->typical_energy = history->typical_energy > 0 ? 0.8 * history->typical_energy + 0.2 * energy : energy;
    }
  }
  return result;
}

}  // namespace gazedirector
