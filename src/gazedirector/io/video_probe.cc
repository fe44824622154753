#include "gazedirector/io/video_probe.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <tuple>
#include <utility>

#include "gazedirector/util/subprocess.h"

namespace gazedirector {
namespace {

// One line of the listing: its section ("packet", "stream") and its fields.
// A field without '=' opens a nested section (a packet's side_data), whose
// fields are not the line's own, so reading stops there.
std::pair<std::string, std::map<std::string, std::string>> ReadListingLine(const std::string& line) {
  std::istringstream parts(line);
  std::string section, part;
  std::getline(parts, section, '|');
  std::map<std::string, std::string> fields;
  while (std::getline(parts, part, '|')) {
    const std::size_t equals = part.find('=');
    if (equals == std::string::npos) break;
    fields[part.substr(0, equals)] = part.substr(equals + 1);
  }
  return {section, fields};
}

std::string FieldOrEmpty(const std::map<std::string, std::string>& fields, const std::string& key) {
  const auto found = fields.find(key);
  return found == fields.end() ? "" : found->second;
}

// `name` where it is one of `known`, else empty.
std::string KnownOrEmpty(const std::string& name, std::initializer_list<const char*> known) {
  for (const char* k : known) {
    if (name == k) return name;
  }
  return "";
}

// The tags that ffmpeg's -colorspace, -color_trc and -color_primaries take
// back ("unknown", "reserved" and rarities are left untagged).
ColourTags KnownColourTags(const std::map<std::string, std::string>& stream) {
  ColourTags tags;
  tags.matrix = KnownOrEmpty(FieldOrEmpty(stream, "color_space"),
                             {"bt709", "bt470bg", "smpte170m", "smpte240m", "fcc", "bt2020nc", "bt2020c"});
  tags.transfer = KnownOrEmpty(FieldOrEmpty(stream, "color_transfer"),
                               {"bt709", "gamma22", "gamma28", "smpte170m", "smpte240m", "linear", "iec61966-2-1",
                                "bt2020-10", "bt2020-12", "smpte2084", "arib-std-b67"});
  tags.primaries = KnownOrEmpty(FieldOrEmpty(stream, "color_primaries"),
                                {"bt709", "bt470m", "bt470bg", "smpte170m", "smpte240m", "film", "bt2020", "smpte431",
                                 "smpte432"});
  return tags;
}

// A number, or `otherwise` where the text is none ("N/A").
double NumberOr(const std::string& text, double otherwise) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  return end != text.c_str() && std::isfinite(value) ? value : otherwise;
}

VideoProbe RunProbe(const std::filesystem::path& video) {
  if (!ProgramExists("ffprobe")) return {};
  const std::optional<std::string> listing = RunForOutput(
      {"ffprobe", "-v", "error", "-show_entries",
       "packet=codec_type,stream_index,pts_time:stream=index,codec_type,codec_name,color_space,color_transfer,"
       "color_primaries",
       "-of", "compact", video.string()});
  return listing ? ParseProbeListing(*listing) : VideoProbe{};
}

}  // namespace

VideoProbe ParseProbeListing(const std::string& listing) {
  VideoProbe probe;
  probe.read = true;
  std::vector<std::pair<int, double>> video_packets;  // (stream, time); NaN where not stated
  int first_video_stream = -1;
  bool audio_seen = false;
  long run = 0;
  std::istringstream lines(listing);
  std::string line;
  while (std::getline(lines, line)) {
    const auto [section, fields] = ReadListingLine(line);
    const std::string type = FieldOrEmpty(fields, "codec_type");
    if (section == "packet") {
      if (type == "video") {
        run = 0;
        video_packets.emplace_back(static_cast<int>(NumberOr(FieldOrEmpty(fields, "stream_index"), -1)),
                                   NumberOr(FieldOrEmpty(fields, "pts_time"), NAN));
      } else {
        probe.longest_run_without_video = std::max(probe.longest_run_without_video, ++run);
      }
    } else if (section == "stream") {
      ++probe.streams;
      if (type == "video" && probe.video_streams++ == 0) {
        first_video_stream = static_cast<int>(NumberOr(FieldOrEmpty(fields, "index"), -1));
        probe.colour = KnownColourTags(fields);
      } else if (type == "audio" && !audio_seen) {
        audio_seen = true;
        probe.audio_codec = FieldOrEmpty(fields, "codec_name");
      }
    }
  }
  for (const auto& [stream, time] : video_packets) {
    if (stream == first_video_stream && std::isfinite(time)) probe.frame_times.push_back(time);
  }
  std::sort(probe.frame_times.begin(), probe.frame_times.end());
  return probe;
}

VideoProbe ProbeVideo(const std::filesystem::path& video) {
  std::error_code ec;
  const auto key = std::make_tuple(std::filesystem::absolute(video, ec).string(), std::filesystem::file_size(video, ec),
                                   std::filesystem::last_write_time(video, ec).time_since_epoch().count());
  static std::mutex mutex;
  static std::map<decltype(key), VideoProbe> probes;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto known = probes.find(key); known != probes.end()) return known->second;
  }
  VideoProbe probe = RunProbe(video);
  const std::lock_guard<std::mutex> lock(mutex);
  probes.emplace(key, probe);
  return probe;
}

}  // namespace gazedirector
