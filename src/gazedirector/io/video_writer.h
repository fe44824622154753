#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "gazedirector/io/atomic_output.h"
#include "gazedirector/io/video_reader.h"
#include "gazedirector/util/subprocess.h"

namespace gazedirector {

struct VideoWriterOptions {
  int width = 0;
  int height = 0;
  FrameRate frame_rate;
  // Audio tracks are copied unchanged from this file when set and present.
  std::filesystem::path audio_source;
  int crf = 18;  // x264 quality: 18 is visually lossless
};

// Encodes BGR frames to H.264 (or GIF for a .gif path) through the ffmpeg
// program, copying the audio of `audio_source`. The output appears only when
// Finish() succeeds; otherwise nothing is left behind.
class VideoWriter {
 public:
  VideoWriter(const std::filesystem::path& path, const VideoWriterOptions& options,
              const std::vector<std::filesystem::path>& inputs = {});
  ~VideoWriter();

  void Write(const cv::Mat& frame);
  void Finish();
  long frames_written() const { return frames_written_; }

 private:
  VideoWriterOptions options_;
  AtomicOutput output_;
  std::unique_ptr<Subprocess> encoder_;
  long frames_written_ = 0;
};

}  // namespace gazedirector
