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
  // The output's constant rate; frames are placed on it by their times (see
  // SteadyFrameRate for a variable-rate source).
  FrameRate frame_rate;
  // The video these frames came from: its audio is copied unchanged where
  // the output's container takes its codec (else converted: Opus for WebM,
  // AAC otherwise), and its metadata (creation time, place, ...) too, when set.
  std::filesystem::path source;
  std::string source_audio_codec = {};  // ProbeVideo(source).audio_codec
  // Written into the output (not GIF) so that players show its colours as the
  // source's: frames are read and written with the same matrix, so the tags
  // of the source describe the output's values too.
  ColourTags colour = {};
  int crf = 18;  // x264 quality: 18 is visually lossless
};

// Options to write the frames of the video `source` again (perhaps `width`
// wide, side by side): its size, a rate on which each frame keeps its time
// (SteadyFrameRate), its colour tags, audio and metadata.
VideoWriterOptions WriterOptionsFor(const std::filesystem::path& source, const VideoInfo& info, int width = 0);

// Encodes BGR frames to H.264 (VP9 for a .webm path, GIF for a .gif path)
// through the ffmpeg program, with the audio and metadata of the source. Each frame is shown from its
// time on: where the next frame comes later than one step of the output's
// rate, it is held (a variable-rate source or a gap), and frames that come
// sooner than one step each still get one. The output appears only when
// Finish() succeeds; otherwise nothing is left behind.
class VideoWriter {
 public:
  VideoWriter(const std::filesystem::path& path, const VideoWriterOptions& options,
              const std::vector<std::filesystem::path>& inputs = {});
  ~VideoWriter();

  void Write(const cv::Mat& frame, double timestamp_s);
  void Finish();
  // Frames given, and frames encoded (with those held over gaps).
  long frames_written() const { return frames_written_; }
  long frames_encoded() const { return next_slot_; }

 private:
  void Encode(const cv::Mat& frame);

  VideoWriterOptions options_;
  AtomicOutput output_;
  std::unique_ptr<Subprocess> encoder_;
  long frames_written_ = 0;
  long next_slot_ = 0;  // the next frame's index on the output's rate
  cv::Mat previous_;
};

}  // namespace gazedirector
