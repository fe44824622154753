#pragma once

#include <filesystem>

#include "gazedirector/face/face_tracker.h"
#include "gazedirector/model/eye_region_model.h"

namespace gazedirector {

// Frames per second of decoding a video and tracking its faces' landmarks
// and head pose (no output written), over the whole video.
double MeasureLandmarksFps(const std::filesystem::path& video, FaceTracker& tracker);

// Full renders (pose, rasterize, shade) of both eye regions of the mean model
// framed in a 200x100 px region of interest, per second, with `threads`
// renderers working at once (the fitter renders this way, one per core).
// Gaze and eyelids move a little every render so that nothing is cached.
double MeasureRendersPerSecond(std::shared_ptr<const EyeRegionModel> model, int threads, double seconds);

}  // namespace gazedirector
