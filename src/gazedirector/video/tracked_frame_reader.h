#pragma once

#include <future>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "gazedirector/face/face.h"
#include "gazedirector/geometry/camera.h"
#include "gazedirector/io/video_reader.h"
#include "gazedirector/video/gaze_tracker.h"

namespace gazedirector {

// A video frame as read, with the faces the tracker found in it.
struct TrackedFrame {
  cv::Mat image;
  long index = -1;
  double timestamp_s = 0;
  std::vector<Face> faces;
};

// Reads a video's frames and tracks their faces (GazeTracker::TrackFaces) one
// frame ahead, on a thread of its own, while the caller fits the frame it was
// given (GazeTracker::FitFaces): decoding and landmarks run mostly on one
// core, and the fits leave part of the second idle. The frames, faces and
// fits are those of reading and tracking in turn.
//
// While it lives, the reader and the tracker's faces are its own: ask the
// reader about the end (EndedEarly, frame_index) after Next returns false.
class TrackedFrameReader {
 public:
  TrackedFrameReader(VideoReader& reader, GazeTracker& tracker, const Camera& camera);
  ~TrackedFrameReader();  // waits for the frame in flight
  TrackedFrameReader(const TrackedFrameReader&) = delete;
  TrackedFrameReader& operator=(const TrackedFrameReader&) = delete;

  // The next frame; false at the end. Rethrows what reading or tracking threw.
  bool Next(TrackedFrame& frame);

 private:
  std::future<std::optional<TrackedFrame>> ReadAhead();

  VideoReader& reader_;
  GazeTracker& tracker_;
  Camera camera_;
  std::future<std::optional<TrackedFrame>> ahead_;
  bool ended_ = false;
};

}  // namespace gazedirector
