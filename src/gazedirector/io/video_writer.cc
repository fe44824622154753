#include "gazedirector/io/video_writer.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "gazedirector/io/media.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace fs = std::filesystem;
namespace {

// VP9's quality for WebM outputs (0-63, lower is better), with its fast
// "realtime" encoder: 40 frames of d3 take 188 kB, x264's crf 18 158 kB.
constexpr int kWebmCrf = 20;

// How the source's audio goes into a container: copied where the container
// takes its codec, else converted. Matroska takes them all.
std::string AudioEncoder(const std::string& extension, const std::string& codec) {
  static const std::map<std::string, std::vector<std::string>> kTakes = {
      {".webm", {"opus", "vorbis"}},
      {".mp4", {"aac", "mp3", "opus", "flac", "alac", "ac3", "eac3"}},
      {".m4v", {"aac", "mp3", "alac", "ac3", "eac3"}},
      {".mov", {"aac", "mp3", "alac", "ac3", "eac3", "pcm_s16le", "pcm_s24le"}},
      {".avi", {"aac", "mp3", "ac3", "pcm_s16le", "pcm_u8"}}};
  const auto takes = kTakes.find(extension);
  if (takes == kTakes.end() || codec.empty()) return "copy";
  if (std::find(takes->second.begin(), takes->second.end(), codec) != takes->second.end()) return "copy";
  return extension == ".webm" ? "libopus" : "aac";
}

}  // namespace

VideoWriterOptions WriterOptionsFor(const fs::path& source, const VideoInfo& info, int width) {
  VideoWriterOptions options;
  options.width = width > 0 ? width : info.width;
  options.height = info.height;
  options.frame_rate = SteadyFrameRate(source, info);
  options.source = source;
  const VideoProbe probe = ProbeVideo(source);
  options.colour = probe.colour;
  options.source_audio_codec = probe.audio_codec;
  return options;
}

VideoWriter::VideoWriter(const fs::path& path, const VideoWriterOptions& options, const std::vector<fs::path>& inputs)
    : options_(options), output_(path, inputs) {
  if (!ProgramExists("ffmpeg")) {
    Fail(ExitCode::kOutput, "writing {} needs the ffmpeg program; install Debian's ffmpeg (bash scripts/setup.sh does)",
         path.string());
  }
  const std::string extension = LowerExtension(path);
  const std::string rate = std::to_string(options.frame_rate.numerator) + "/" + std::to_string(options.frame_rate.denominator);
  std::vector<std::string> argv = {"ffmpeg", "-hide_banner", "-nostdin", "-loglevel", "error", "-y",
                                   "-f", "rawvideo", "-pix_fmt", "bgr24",
                                   "-s", std::to_string(options.width) + "x" + std::to_string(options.height),
                                   "-framerate", rate, "-i", "pipe:0"};
  const bool gif = extension == ".gif";
  // WebM holds VP9 (and Opus or Vorbis audio), not H.264.
  const bool webm = extension == ".webm";
  if (!gif && !options.source.empty()) {
    // Only the container's metadata: the source's display turn, the video
    // stream's, is already in the frames, which are written upright.
    argv.insert(argv.end(), {"-i", options.source.string(), "-map", "0:v:0", "-map", "1:a?", "-c:a",
                             AudioEncoder(extension, options.source_audio_codec), "-map_metadata", "1"});
  }
  if (gif) {
    argv.insert(argv.end(), {"-vf", "split[a][b];[a]palettegen=stats_mode=diff[p];[b][p]paletteuse=dither=bayer"});
  } else {
    const bool even = options.width % 2 == 0 && options.height % 2 == 0;
    // 4:2:0 colour halves each side, so an odd side cannot be kept in it.
    if (!even) {
      spdlog::warn("{}: the frames are {}x{}, an odd size, so the video is written with full colour resolution "
                   "(4:4:4), which some players (web browsers, QuickTime) do not play",
                   path.string(), options.width, options.height);
    }
    // swscale's default RGB to YUV conversion truncates: frames came out about
    // 1 grey level darker than they went in, and 2 after decoding.
    if (webm) {
      argv.insert(argv.end(), {"-c:v", "libvpx-vp9", "-crf", std::to_string(kWebmCrf), "-b:v", "0", "-deadline",
                               "realtime", "-cpu-used", "5", "-row-mt", "1"});
    } else {
      argv.insert(argv.end(), {"-c:v", "libx264", "-preset", "veryfast", "-crf", std::to_string(options.crf)});
    }
    argv.insert(argv.end(), {"-pix_fmt", even ? "yuv420p" : "yuv444p", "-r", rate, "-sws_flags", "bicubic+accurate_rnd"});
    const ColourTags& colour = options.colour;
    if (!colour.matrix.empty()) argv.insert(argv.end(), {"-colorspace", colour.matrix});
    if (!colour.transfer.empty()) argv.insert(argv.end(), {"-color_trc", colour.transfer});
    if (!colour.primaries.empty()) argv.insert(argv.end(), {"-color_primaries", colour.primaries});
    if (extension == ".mp4" || extension == ".mov" || extension == ".m4v") argv.insert(argv.end(), {"-movflags", "+faststart"});
  }
  argv.push_back(output_.temp_path().string());
  encoder_ = std::make_unique<Subprocess>(argv);
}

VideoWriter::~VideoWriter() = default;

void VideoWriter::Write(const cv::Mat& frame, double timestamp_s) {
  CV_Assert(frame.type() == CV_8UC3 && frame.cols == options_.width && frame.rows == options_.height);
  // A gap longer than this is a broken time, not a pause worth filling.
  constexpr double kLongestHold_s = 60;
  const double rate = options_.frame_rate.value();
  const double slot = std::isfinite(timestamp_s) ? std::round(timestamp_s * rate) : 0.0;
  if (slot > next_slot_ && slot - next_slot_ <= kLongestHold_s * rate) {
    // A video starting late shows its first frame from the start.
    const cv::Mat& held = previous_.empty() ? frame : previous_;
    while (next_slot_ < slot) Encode(held);
  }
  Encode(frame);
  frame.copyTo(previous_);
  ++frames_written_;
}

void VideoWriter::Encode(const cv::Mat& frame) {
  const cv::Mat contiguous = frame.isContinuous() ? frame : frame.clone();
  if (!encoder_->Write(contiguous.data, contiguous.total() * contiguous.elemSize())) {
    const std::string message = encoder_->ErrorOutput();
    encoder_->Kill();
    Fail(ExitCode::kOutput, "ffmpeg stopped while writing {}: {}", output_.path().string(), message);
  }
  ++next_slot_;
}

void VideoWriter::Finish() {
  const int status = encoder_->Finish();
  if (status != 0) {
    Fail(ExitCode::kOutput, "ffmpeg failed to write {}: {}", output_.path().string(), encoder_->ErrorOutput());
  }
  output_.Commit();
}

}  // namespace gazedirector
