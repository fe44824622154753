#include "gazedirector/io/video_reader.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include "gazedirector/io/image_io.h"
#include "gazedirector/io/media.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/subprocess.h"
#include "gazedirector/util/temporary_folder.h"

namespace gazedirector {

FrameRate FrameRate::FromDouble(double fps) {
  if (!(fps > 0) || !std::isfinite(fps)) return {30, 1};
  for (int denominator : {1, 1001, 2, 4, 5, 10, 100, 1000}) {
    const double numerator = fps * denominator;
    if (std::abs(numerator - std::round(numerator)) < 1e-3 * denominator) {
      return {static_cast<int>(std::round(numerator)), denominator};
    }
  }
  return {static_cast<int>(std::round(fps * 1000)), 1000};
}

namespace {

// OpenCV 4.6's FFmpeg reader gives up on a stream after 512 packets of other
// streams in a row (a limit fixed in its code), so where a video's audio runs
// on for ten seconds or so past its last frame, or past a frame that stays on
// screen that long, the reading stopped there: at the end, the frames its
// decoder still held were lost (three of an H.264 clip's, one of a VP9 one's).
constexpr long kMostPacketsBetweenFrames = 256;

// A copy of the video's first video stream alone (no re-encoding), in a
// temporary file of the same format; empty where ffmpeg cannot make it.
std::filesystem::path CopyVideoStreamAlone(const std::filesystem::path& video) {
  const std::filesystem::path copy = UniqueTemporaryPath("-video" + video.extension().string());
  if (!ProgramExists("ffmpeg") ||
      !RunForOutput({"ffmpeg", "-nostdin", "-v", "error", "-y", "-i", video.string(), "-map", "0:v:0", "-c", "copy",
                     copy.string()})) {
    std::error_code ignored;
    std::filesystem::remove(copy, ignored);
    return {};
  }
  return copy;
}

}  // namespace

VideoReader::VideoReader(const std::filesystem::path& path) : path_(path) {
  if (DetectMediaKind(path) != MediaKind::kVideo) Fail(ExitCode::kBadInput, "{}: not a video", path.string());
  const VideoProbe probe = ProbeVideo(path);
  if (probe.longest_run_without_video > kMostPacketsBetweenFrames) video_alone_.path = CopyVideoStreamAlone(path);
  capture_ = std::make_unique<cv::VideoCapture>();
  try {
    capture_->open((video_alone_.path.empty() ? path : video_alone_.path).string(), cv::CAP_FFMPEG);
  } catch (const cv::Exception& e) {
    Fail(ExitCode::kBadInput, "{}: cannot open the video ({})", path.string(), e.err);
  }
  if (!capture_->isOpened()) {
    if (probe.streams > 0 && probe.video_streams == 0) {
      Fail(ExitCode::kBadInput, "{}: holds no video stream (only audio?)", path.string());
    }
    Fail(ExitCode::kBadInput, "{}: cannot open the video (truncated, corrupt or unsupported)", path.string());
  }
  // OpenCV 4.6 (Debian 12's) turns a video stored a quarter turn from upright
  // the wrong way (opencv/opencv#22088), so a phone's portrait video came out
  // upside down. Read the frames as stored and turn them as ffmpeg and players do.
  const bool stored = capture_->set(cv::CAP_PROP_ORIENTATION_AUTO, 0) && capture_->get(cv::CAP_PROP_ORIENTATION_AUTO) == 0;
  const int meta = static_cast<int>(std::lround(capture_->get(cv::CAP_PROP_ORIENTATION_META)));
  counterclockwise_deg_ = stored ? ((meta % 360) + 360) % 360 : 0;  // never turned twice
  if (counterclockwise_deg_ % 90 != 0) counterclockwise_deg_ = 0;
  info_.width = static_cast<int>(capture_->get(cv::CAP_PROP_FRAME_WIDTH));
  info_.height = static_cast<int>(capture_->get(cv::CAP_PROP_FRAME_HEIGHT));
  if (counterclockwise_deg_ == 90 || counterclockwise_deg_ == 270) std::swap(info_.width, info_.height);
  info_.frame_rate = FrameRate::FromDouble(capture_->get(cv::CAP_PROP_FPS));
  info_.frame_count = std::max(0L, static_cast<long>(capture_->get(cv::CAP_PROP_FRAME_COUNT)));
  if (info_.width < kMinImageSide || info_.height < kMinImageSide) {
    Fail(ExitCode::kBadInput, "{}: the video is {}x{} pixels; too small to hold a face", path.string(), info_.width,
         info_.height);
  }
}

VideoReader::~VideoReader() = default;

VideoReader::TemporaryFile::~TemporaryFile() {
  std::error_code ignored;
  if (!path.empty()) std::filesystem::remove(path, ignored);
}

bool VideoReader::Read(cv::Mat& frame) {
  if (ended_) return false;
  cv::Mat decoded;
  bool ok = false;
  try {
    ok = capture_->read(decoded);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok || decoded.empty()) {
    ended_ = true;
    if (frame_index_ < 0) Fail(ExitCode::kBadInput, "{}: no frame could be decoded", path_.string());
    return false;
  }
  frame = decoded.type() == CV_8UC3 ? decoded : ToBgr8(decoded);
  switch (counterclockwise_deg_) {
    case 90: cv::rotate(frame, frame, cv::ROTATE_90_COUNTERCLOCKWISE); break;
    case 180: cv::rotate(frame, frame, cv::ROTATE_180); break;
    case 270: cv::rotate(frame, frame, cv::ROTATE_90_CLOCKWISE); break;
    default: break;
  }
  ++frame_index_;
  // Decoders flush their last frames without a time (OpenCV then states 0):
  // those, and any time that does not move forward, follow at the last step.
  const double stated = capture_->get(cv::CAP_PROP_POS_MSEC) / 1000;
  if (frame_index_ == 0) {
    timestamp_s_ = std::isfinite(stated) ? std::max(stated, 0.0) : 0.0;
    last_step_s_ = 1 / info_.frame_rate.value();
  } else if (std::isfinite(stated) && stated > timestamp_s_) {
    last_step_s_ = stated - timestamp_s_;
    timestamp_s_ = stated;
  } else {
    timestamp_s_ += last_step_s_;
  }
  return true;
}

bool VideoReader::EndedEarly() const {
  return ended_ && info_.frame_count > 0 && frame_index_ + 1 < info_.frame_count - 1;
}

FrameRate SteadyFrameRate(const std::filesystem::path& video, const VideoInfo& info) {
  constexpr std::size_t kStretch = 10;  // frames: shorter bursts may shift by a frame or two
  constexpr double kMaxRate = 120;
  // At most this many frames written per frame read on average: a screen
  // recording idling at 1 fps between bursts at 60 would otherwise be written
  // 60 times over. Its bursts then fall behind and catch up while it idles.
  constexpr double kMaxFramesPerFrame = 4;
  const std::vector<double> times = ProbeVideo(video).frame_times;
  if (times.size() < 3 || !(times.back() > times.front())) return info.frame_rate;
  const std::size_t window = std::min(kStretch, times.size() - 1);
  double densest = std::numeric_limits<double>::infinity();  // the shortest mean interval over `window` frames
  for (std::size_t i = 0; i + window < times.size(); ++i) {
    densest = std::min(densest, (times[i + window] - times[i]) / window);
  }
  if (!(densest > 0)) return info.frame_rate;
  const double average = (times.size() - 1) / (times.back() - times.front());
  const double cap = std::min(kMaxRate, kMaxFramesPerFrame * average);
  const double rate = 1 / densest > cap ? std::max(1.0, std::floor(cap)) : 1 / densest;
  // Within 1% the stated rate stands: times stored to the microsecond jitter that much.
  return rate > 1.01 * info.frame_rate.value() ? FrameRate::FromDouble(rate) : info.frame_rate;
}

}  // namespace gazedirector
