#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "gazedirector/io/video_probe.h"

namespace cv {
class VideoCapture;
}

namespace gazedirector {

// A frame rate as a fraction, as containers store it (30000/1001 for NTSC).
struct FrameRate {
  int numerator = 30;
  int denominator = 1;
  double value() const { return static_cast<double>(numerator) / denominator; }
  // The nearest common fraction to a rate given as a number.
  static FrameRate FromDouble(double fps);
};

struct VideoInfo {
  int width = 0;
  int height = 0;
  FrameRate frame_rate;
  long frame_count = 0;  // as the container states it; may be approximate
  double duration_s() const { return frame_count / frame_rate.value(); }
};

// Decodes a video file frame by frame as 8-bit BGR, turned upright as its
// container asks (phone videos), as ffmpeg shows it. Fails with
// ExitCode::kBadInput when the file cannot be opened or holds no frame.
class VideoReader {
 public:
  explicit VideoReader(const std::filesystem::path& path);
  ~VideoReader();

  const VideoInfo& info() const { return info_; }
  // False at the end of the stream.
  bool Read(cv::Mat& frame);
  // The index and presentation time (seconds from the first frame) of the
  // frame last read, as the container times it: frames of a variable-rate
  // video keep their own times.
  long frame_index() const { return frame_index_; }
  double timestamp_s() const { return timestamp_s_; }
  // True when the stream stopped well before the frame count the container
  // announced (a truncated file).
  bool EndedEarly() const;

 private:
  std::filesystem::path path_;
  // A file removed when the reader goes, or when its constructor fails.
  struct TemporaryFile {
    std::filesystem::path path;
    ~TemporaryFile();
  };
  // Where the video stream is read from a copy of its own (video_reader.cc's
  // kMostPacketsBetweenFrames says why); declared before capture_, which
  // closes it first.
  TemporaryFile video_alone_;
  std::unique_ptr<cv::VideoCapture> capture_;
  VideoInfo info_;
  int counterclockwise_deg_ = 0;  // the display turn the container asks for: 0, 90, 180 or 270
  long frame_index_ = -1;
  double timestamp_s_ = 0;
  double last_step_s_ = 0;  // the interval before the frame last read
  bool ended_ = false;
};

// The constant rate at which a video's frames can be written again so that
// each keeps its time: the stated rate, or for a variable-rate video the rate
// of its densest stretch (at most 120 fps and 4 times the average), so that no
// frame is dropped (slower stretches repeat frames). Reads the frame times
// with ffprobe; the stated rate where ffprobe is missing or the times cannot
// be read.
FrameRate SteadyFrameRate(const std::filesystem::path& video, const VideoInfo& info);

}  // namespace gazedirector
