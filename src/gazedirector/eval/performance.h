#pragma once

#include <filesystem>

#include "gazedirector/face/face_tracker.h"

namespace gazedirector {

// Frames per second of decoding a video and tracking its faces' landmarks
// and head pose (no output written), over the whole video.
double MeasureLandmarksFps(const std::filesystem::path& video, FaceTracker& tracker);

}  // namespace gazedirector
