#pragma once

#include <filesystem>

#include "gazedirector/face/face_tracker.h"
#include "gazedirector/model/eye_region_model.h"

#include <vector>
#include <opencv2/core.hpp>

namespace gazedirector {

// Frames per second of decoding a video and tracking its faces' landmarks
// and head pose (no output written), over the whole video.
double MeasureLandmarksFps(const std::filesystem::path& video, FaceTracker& tracker);

// Full renders (pose, rasterize, shade) of both eye regions of the mean model
// framed in a 200x100 px region of interest, per second, with `threads`
// renderers working at once (the fitter renders this way, one per core).
// Gaze and eyelids move a little every render so that nothing is cached.
double MeasureRendersPerSecond(std::shared_ptr<const EyeRegionModel> model, int threads, double seconds);

// The first `max_frames` frames of a video, decoded, with the largest face's
// landmarks tracked in each (frames without a face are dropped).
struct TrackedClip {
  Camera camera;
  std::vector<cv::Mat> frames;
  std::vector<Face> faces;
};
TrackedClip LoadTrackedClip(const std::filesystem::path& video, FaceTracker& tracker, int max_frames);

// Model fits per second of both eyes of one face in consecutive frames of
// `clip`, each warm-started from the previous frame's fit with the settled
// parameters held, as the video tracker fits (landmarks given, not timed).
double MeasureFitFps(std::shared_ptr<const EyeRegionModel> model, const TrackedClip& clip);

// Frames per second of the whole tracking stage on a video: decoding,
// landmarks and head pose, and the model fits (up to `max_frames`).
double MeasureTrackFps(std::shared_ptr<const EyeRegionModel> model, std::shared_ptr<const LandmarkDetector> landmarks,
                       const MeanFace& mean_face, const std::filesystem::path& video, int max_frames);

// Frames per second of redirecting fitted frames of `clip` to the camera
// (flow warp, eyeball compositing, reflections; fits made beforehand, not timed).
double MeasureRedirectFps(std::shared_ptr<const EyeRegionModel> model, const TrackedClip& clip);

}  // namespace gazedirector
