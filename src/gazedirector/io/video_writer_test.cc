#include "gazedirector/io/video_writer.h"

#include <cmath>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "gazedirector/io/video_reader.h"
#include "gazedirector/util/subprocess.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;

// Frame i is a flat grey of 20 i, so that every encoded frame tells which
// frame it shows.
cv::Mat NumberedFrame(int i) { return cv::Mat(64, 64, CV_8UC3, cv::Scalar::all(20 * i)); }

// The numbers of the frames a video shows, one per encoded frame.
std::vector<int> ShownNumbers(const fs::path& video) {
  VideoReader reader(video);
  std::vector<int> numbers;
  cv::Mat frame;
  while (reader.Read(frame)) numbers.push_back(cvRound(cv::mean(frame)[0] / 20));
  return numbers;
}

// What ffprobe says of a video's `entries`, one value per line ("none" without an answer).
std::string Probe(const fs::path& video, const std::string& entries, bool count_frames = false) {
  std::vector<std::string> argv = {"ffprobe", "-v", "error", "-show_entries", entries, "-of", "csv=p=0", video.string()};
  if (count_frames) argv.insert(argv.begin() + 1, "-count_frames");
  return RunForOutput(argv).value_or("none");
}

TEST(VideoWriterTest, HoldsEachFrameUntilTheNextOnesTimeAndDropsNone) {
  ASSERT_TRUE(ProgramExists("ffmpeg")) << "bash scripts/setup.sh installs ffmpeg";
  const fs::path path = ScratchDir("video_writer") / "variable.mp4";
  // ffmpeg's messages go to a temporary file, which a $TMPDIR naming no folder made fail.
  const testing::ScopedEnv tmpdir("TMPDIR", (path.parent_path() / "no such folder").string());
  // 10 fps, then a stretch at 30 fps, a pause of 0.2 s, then 30 fps again.
  const std::vector<double> times = {0, 0.1, 0.2, 0.2333, 0.2667, 0.3, 0.5, 0.5333, 0.5667, 0.6};
  VideoWriter writer(path, VideoWriterOptions{64, 64, FrameRate{30, 1}, {}});
  for (int i = 0; i < static_cast<int>(times.size()); ++i) writer.Write(NumberedFrame(i), times[i]);
  writer.Finish();
  EXPECT_EQ(writer.frames_written(), 10);
  EXPECT_EQ(writer.frames_encoded(), 19);

  // Output frame k (at k / 30 s) shows the last frame whose time is at or before it.
  const std::vector<int> expected = {0, 0, 0, 1, 1, 1, 2, 3, 4, 5, 5, 5, 5, 5, 5, 6, 7, 8, 9};
  EXPECT_EQ(ShownNumbers(path), expected);
}

TEST(VideoWriterTest, GivesFramesThatComeSoonerThanOneStepEachAFrame) {
  ASSERT_TRUE(ProgramExists("ffmpeg")) << "bash scripts/setup.sh installs ffmpeg";
  const fs::path path = ScratchDir("video_writer") / "dense.mp4";
  VideoWriter writer(path, VideoWriterOptions{64, 64, FrameRate{10, 1}, {}});
  // Three frames inside one step of 0.1 s, then one that starts late by a broken time.
  const std::vector<double> times = {0.02, 0.03, 0.04, 1e9};
  for (int i = 0; i < static_cast<int>(times.size()); ++i) writer.Write(NumberedFrame(i), times[i]);
  writer.Finish();
  EXPECT_EQ(ShownNumbers(path), (std::vector<int>{0, 1, 2, 3}));
}

// 4:2:0 colour cannot hold an odd side, so such a video keeps its size in
// 4:4:4, and says that some players will not play it.
TEST(VideoWriterTest, AnOddSizedVideoKeepsItsSizeAndWarnsOfItsPlayers) {
  ASSERT_TRUE(ProgramExists("ffmpeg") && ProgramExists("ffprobe")) << "bash scripts/setup.sh installs ffmpeg";
  const fs::path dir = ScratchDir("video_writer");
  for (const auto& [name, width, height] : {std::tuple{"odd.mp4", 33, 17}, {"odd.webm", 32, 17}, {"even.mp4", 32, 18}}) {
    const testing::CapturedLog log;
    VideoWriter writer(dir / name, VideoWriterOptions{width, height, FrameRate{10, 1}, {}});
    for (int i = 0; i < 3; ++i) writer.Write(cv::Mat(height, width, CV_8UC3, cv::Scalar::all(20 * i)), i / 10.0);
    writer.Finish();
    const bool odd = width % 2 != 0 || height % 2 != 0;
    EXPECT_EQ(Probe(dir / name, "stream=width,height,pix_fmt"),
              fmt::format("{},{},{}\n", width, height, odd ? "yuv444p" : "yuv420p")) << name;
    EXPECT_EQ(log.text().find("some players") != std::string::npos, odd) << name << ": " << log.text();
  }
}

// Frames read from a real video and written again keep their colours: the
// same values (up to the encoder's loss; before, swscale's truncating RGB to
// YUV made them 2 grey levels darker through a read and a write) and the
// source's colour tags, so that players show them as the source (d10.mp4 is
// BT.709, which players told nothing take for BT.601 at this size).
TEST(VideoWriterTest, AVideoWrittenAgainKeepsItsColours) {
  ASSERT_TRUE(ProgramExists("ffmpeg") && ProgramExists("ffprobe")) << "bash scripts/setup.sh installs ffmpeg";
  const fs::path source = testing::DataPath("video/d10.mp4");
  const fs::path path = ScratchDir("video_writer") / "again.mp4";
  VideoReader reader(source);
  VideoWriterOptions options = WriterOptionsFor(source, reader.info());
  options.source.clear();  // its audio, 15 s long, would outlast these frames
  EXPECT_EQ(options.colour, (ColourTags{"bt709", "bt709", "bt709"}));
  std::vector<cv::Mat> frames;
  {
    VideoWriter writer(path, options);
    cv::Mat frame;
    while (frames.size() < 15 && reader.Read(frame)) {
      frames.push_back(frame.clone());
      writer.Write(frame, reader.timestamp_s());
    }
    writer.Finish();
  }
  EXPECT_EQ(ProbeVideo(path).colour, options.colour);
  VideoReader again(path);
  cv::Mat frame;
  cv::Scalar difference;
  for (const cv::Mat& original : frames) {
    ASSERT_TRUE(again.Read(frame));
    cv::Mat signed_difference;
    cv::subtract(frame, original, signed_difference, cv::noArray(), CV_32F);
    difference += cv::mean(signed_difference) / static_cast<double>(frames.size());
  }
  // What is left is the reader's own rounding (OpenCV decodes with swscale's
  // fast path), about a grey level.
  for (int channel = 0; channel < 3; ++channel) EXPECT_LT(std::abs(difference[channel]), 1.6) << channel;
  EXPECT_EQ(ProbeVideo(testing::DataPath("video/d3.mp4")).colour, ColourTags{});  // untagged: left so
}

// The source's audio and the container's metadata (d10.mp4's creation time)
// come along.
TEST(VideoWriterTest, AVideoWrittenAgainKeepsItsAudioAndMetadata) {
  ASSERT_TRUE(ProgramExists("ffmpeg") && ProgramExists("ffprobe")) << "bash scripts/setup.sh installs ffmpeg";
  const fs::path source = testing::DataPath("video/d10.mp4");
  const fs::path path = ScratchDir("video_writer") / "metadata.mp4";
  VideoReader reader(source);
  {
    VideoWriter writer(path, WriterOptionsFor(source, reader.info()));
    cv::Mat frame;
    for (int i = 0; i < 5 && reader.Read(frame); ++i) writer.Write(frame, reader.timestamp_s());
    writer.Finish();
  }
  EXPECT_EQ(Probe(path, "format_tags=creation_time"), "2024-07-11T07:56:57.000000Z\n");
  EXPECT_EQ(Probe(path, "stream=codec_type"), "video\naudio\n");
}

// A WebM output holds VP9 and Opus: the source's H.264 frames are encoded
// again and its AAC audio is converted rather than copied (which WebM refuses);
// so is audio that another container does not take.
TEST(VideoWriterTest, AWebmOutputKeepsItsFramesAndAudioAndAnyContainerTakesItsAudio) {
  ASSERT_TRUE(ProgramExists("ffmpeg") && ProgramExists("ffprobe")) << "bash scripts/setup.sh installs ffmpeg";
  const fs::path source = testing::DataPath("video/d10.mp4");
  const fs::path dir = ScratchDir("video_writer_webm");
  const fs::path path = dir / "web.webm";
  VideoReader reader(source);
  std::vector<cv::Mat> frames;
  {
    VideoWriter writer(path, WriterOptionsFor(source, reader.info()));
    cv::Mat frame;
    for (int i = 0; i < 10 && reader.Read(frame); ++i) {
      writer.Write(frame, reader.timestamp_s());
      frames.push_back(frame.clone());
    }
    writer.Finish();
  }
  const std::string streams = Probe(path, "stream=codec_name,nb_read_frames", /*count_frames=*/true);
  // Ten video frames; the audio is the source's whole track.
  EXPECT_EQ(streams.substr(0, streams.find('\n')), "vp9,10") << streams;
  EXPECT_EQ(streams.substr(streams.find('\n') + 1, 5), "opus,") << streams;
  // All ten read back, though their audio runs 15 s past them (VideoReaderTest.ReadsEveryFrameOfAVideoWhoseAudioOutlastsIt).
  VideoReader written(path);
  cv::Mat frame;
  std::size_t count = 0;
  for (; written.Read(frame); ++count) {
    ASSERT_LT(count, frames.size());
    cv::Mat difference;
    cv::absdiff(frame, frames[count], difference);
    const cv::Scalar mean = cv::mean(difference);
    EXPECT_LT((mean[0] + mean[1] + mean[2]) / 3, 3.0) << "frame " << count;
  }
  EXPECT_EQ(count, frames.size());

  EXPECT_EQ(ProbeVideo(source).audio_codec, "aac");
  EXPECT_EQ(ProbeVideo(path).audio_codec, "opus");
  // Written again as QuickTime, whose container takes no Opus: the audio becomes AAC.
  const fs::path mov = dir / "from_web.mov";
  {
    VideoReader web(path);
    VideoWriter writer(mov, WriterOptionsFor(path, web.info()));
    for (int i = 0; i < 3 && web.Read(frame); ++i) writer.Write(frame, web.timestamp_s());
    writer.Finish();
  }
  EXPECT_EQ(Probe(mov, "stream=codec_name"), "h264\naac\n");
}

}  // namespace
}  // namespace gazedirector
