#include "gazedirector/video/tracked_frame_reader.h"

#include <utility>

namespace gazedirector {

TrackedFrameReader::TrackedFrameReader(VideoReader& reader, GazeTracker& tracker, const Camera& camera)
    : reader_(reader), tracker_(tracker), camera_(camera), ahead_(ReadAhead()) {}

TrackedFrameReader::~TrackedFrameReader() {
  if (ahead_.valid()) ahead_.wait();
}

std::future<std::optional<TrackedFrame>> TrackedFrameReader::ReadAhead() {
  return std::async(std::launch::async, [this]() -> std::optional<TrackedFrame> {
    TrackedFrame frame;
    if (!reader_.Read(frame.image)) return std::nullopt;
    frame.index = reader_.frame_index();
    frame.timestamp_s = reader_.timestamp_s();
    frame.faces = tracker_.TrackFaces(frame.image, frame.timestamp_s, camera_);
    return frame;
  });
}

bool TrackedFrameReader::Next(TrackedFrame& frame) {
  if (ended_) return false;
  std::optional<TrackedFrame> next;
  try {
    next = ahead_.get();
  } catch (...) {
    ended_ = true;
    throw;
  }
  if (!next) {
    ended_ = true;
    return false;
  }
  frame = std::move(*next);
  ahead_ = ReadAhead();
  return true;
}

}  // namespace gazedirector
