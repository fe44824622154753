#include "gazedirector/io/video_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <tuple>
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

// The video stream's packet times in seconds, in presentation order.
std::vector<double> ProbeFrameTimes(const std::filesystem::path& video) {
  if (!ProgramExists("ffprobe")) return {};
  const std::optional<std::string> output =
      RunForOutput({"ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries", "packet=pts_time", "-of",
                    "csv=p=0", video.string()});
  std::vector<double> times;
  if (!output) return times;
  std::istringstream lines(*output);
  std::string line;
  while (std::getline(lines, line)) {
    char* end = nullptr;
    const double time = std::strtod(line.c_str(), &end);
    if (end != line.c_str() && std::isfinite(time)) times.push_back(time);
  }
  std::sort(times.begin(), times.end());
  return times;
}

// `name` where it is one of `known`, else empty.
std::string KnownOrEmpty(const std::string& name, std::initializer_list<const char*> known) {
  for (const char* k : known) {
    if (name == k) return name;
  }
  return "";
}

// True only when ffprobe reads the file and lists no video stream in it.
bool HoldsNoVideoStream(const std::filesystem::path& path) {
  if (!ProgramExists("ffprobe")) return false;
  const std::optional<std::string> streams = RunForOutput(
      {"ffprobe", "-v", "error", "-show_entries", "stream=codec_type", "-of", "csv=p=0", path.string()});
  return streams && !streams->empty() && streams->find("video") == std::string::npos;
}

// OpenCV 4.6's FFmpeg reader gives up on a stream after 512 packets of other
// streams in a row (a limit fixed in its code), so where a video's audio runs
// on for ten seconds or so past its last frame, or past a frame that stays on
// screen that long, the reading stopped there: at the end, the frames its
// decoder still held were lost (three of an H.264 clip's, one of a VP9 one's).
constexpr long kMostPacketsBetweenFrames = 256;

// The longest run of other streams' packets before, between or after the
// video stream's packets, in the file's order; 0 where ffprobe is missing or
// cannot read the file.
long LongestRunWithoutVideo(const std::filesystem::path& video) {
  if (!ProgramExists("ffprobe")) return 0;
  const std::optional<std::string> output = RunForOutput(
      {"ffprobe", "-v", "error", "-show_entries", "packet=codec_type", "-of", "csv=p=0", video.string()});
  if (!output) return 0;
  std::istringstream lines(*output);
  std::string line;
  long run = 0, longest = 0;
  while (std::getline(lines, line)) {
    run = line.rfind("video", 0) == 0 ? 0 : run + 1;
    longest = std::max(longest, run);
  }
  return longest;
}

// LongestRunWithoutVideo, asked once per file and process: a command may read
// its input more than once (redirect tracks it, then renders it).
long LongestRunWithoutVideoOnce(const std::filesystem::path& video) {
  std::error_code ec;
  const auto key = std::make_tuple(std::filesystem::absolute(video, ec).string(), std::filesystem::file_size(video, ec),
                                   std::filesystem::last_write_time(video, ec).time_since_epoch().count());
  static std::mutex mutex;
  static std::map<decltype(key), long> runs;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto known = runs.find(key); known != runs.end()) return known->second;
  }
  const long run = LongestRunWithoutVideo(video);
  const std::lock_guard<std::mutex> lock(mutex);
  runs[key] = run;
  return run;
}

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
  if (LongestRunWithoutVideoOnce(path) > kMostPacketsBetweenFrames) video_alone_.path = CopyVideoStreamAlone(path);
  capture_ = std::make_unique<cv::VideoCapture>();
  try {
    capture_->open((video_alone_.path.empty() ? path : video_alone_.path).string(), cv::CAP_FFMPEG);
  } catch (const cv::Exception& e) {
    Fail(ExitCode::kBadInput, "{}: cannot open the video ({})", path.string(), e.err);
  }
  if (!capture_->isOpened()) {
    if (HoldsNoVideoStream(path)) Fail(ExitCode::kBadInput, "{}: holds no video stream (only audio?)", path.string());
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

ColourTags ProbeColourTags(const std::filesystem::path& video) {
  if (!ProgramExists("ffprobe")) return {};
  const std::optional<std::string> output =
      RunForOutput({"ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
                    "stream=color_space,color_transfer,color_primaries", "-of", "default=noprint_wrappers=1",
                    video.string()});
  ColourTags tags;
  if (!output) return tags;
  std::istringstream lines(*output);
  std::string line;
  while (std::getline(lines, line)) {
    const std::size_t equals = line.find('=');
    if (equals == std::string::npos) continue;
    const std::string key = line.substr(0, equals), value = line.substr(equals + 1);
    // Those that ffmpeg's -colorspace, -color_trc and -color_primaries take
    // back ("unknown", "reserved" and rarities are left untagged).
    if (key == "color_space") {
      tags.matrix = KnownOrEmpty(value, {"bt709", "bt470bg", "smpte170m", "smpte240m", "fcc", "bt2020nc", "bt2020c"});
    } else if (key == "color_transfer") {
      tags.transfer = KnownOrEmpty(value, {"bt709", "gamma22", "gamma28", "smpte170m", "smpte240m", "linear",
                                           "iec61966-2-1", "bt2020-10", "bt2020-12", "smpte2084", "arib-std-b67"});
    } else if (key == "color_primaries") {
      tags.primaries = KnownOrEmpty(value, {"bt709", "bt470m", "bt470bg", "smpte170m", "smpte240m", "film", "bt2020",
                                            "smpte431", "smpte432"});
    }
  }
  return tags;
}

std::string ProbeAudioCodec(const std::filesystem::path& video) {
  if (!ProgramExists("ffprobe")) return "";
  const std::optional<std::string> output =
      RunForOutput({"ffprobe", "-v", "error", "-select_streams", "a:0", "-show_entries", "stream=codec_name", "-of",
                    "csv=p=0", video.string()});
  if (!output) return "";
  return output->substr(0, output->find_first_of("\r\n,"));
}

FrameRate SteadyFrameRate(const std::filesystem::path& video, const VideoInfo& info) {
  constexpr std::size_t kStretch = 10;  // frames: shorter bursts may shift by a frame or two
  constexpr double kMaxRate = 120;
  // At most this many frames written per frame read on average: a screen
  // recording idling at 1 fps between bursts at 60 would otherwise be written
  // 60 times over. Its bursts then fall behind and catch up while it idles.
  constexpr double kMaxFramesPerFrame = 4;
  const std::vector<double> times = ProbeFrameTimes(video);
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
