#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace gazedirector {

// How a video's stored colour values are to be shown: the YUV matrix, the
// transfer curve and the primaries, as ffmpeg names them ("bt709", ...);
// empty where the file does not say (players then guess).
struct ColourTags {
  std::string matrix, transfer, primaries;
  bool operator==(const ColourTags&) const = default;
};

// What ffprobe reads from a video file that OpenCV's reader does not tell.
// Everything is empty (and `read` false) where ffprobe is missing or cannot
// read the file.
struct VideoProbe {
  bool read = false;
  int streams = 0;
  int video_streams = 0;
  // The longest run of other streams' packets before, between or after the
  // video packets, in the file's order.
  long longest_run_without_video = 0;
  // The first video stream's packet times in seconds, ascending.
  std::vector<double> frame_times;
  // The first video stream's colour tags; only names ffmpeg accepts back.
  ColourTags colour;
  // The first audio stream's codec as ffmpeg names it ("aac", "opus", ...).
  std::string audio_codec;
};

// Probes `video` with one ffprobe run (every packet and stream), once per
// process and file, keyed by path, size and time stamp: a command reads its
// input more than once (`redirect` tracks it, renders it, and writes its
// output with the source's frame times, colours and audio).
VideoProbe ProbeVideo(const std::filesystem::path& video);

// ProbeVideo's reading of ffprobe's listing (`-of compact`: one line per
// packet and stream, fields as key=value between '|').
VideoProbe ParseProbeListing(const std::string& listing);

}  // namespace gazedirector
