#pragma once

#include <filesystem>
#include <memory>

#include <opencv2/core.hpp>

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
  // The index and timestamp (seconds) of the frame last read.
  long frame_index() const { return frame_index_; }
  double timestamp_s() const { return frame_index_ / info_.frame_rate.value(); }
  // True when the stream stopped well before the frame count the container
  // announced (a truncated file).
  bool EndedEarly() const;

 private:
  std::filesystem::path path_;
  std::unique_ptr<cv::VideoCapture> capture_;
  VideoInfo info_;
  int counterclockwise_deg_ = 0;  // the display turn the container asks for: 0, 90, 180 or 270
  long frame_index_ = -1;
  bool ended_ = false;
};

}  // namespace gazedirector
