#include "gazedirector/io/video_probe.h"

#include <string>

#include <gtest/gtest.h>

#include "gazedirector/io/video_reader.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/subprocess.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;
using testing::DataPath;
using testing::Quote;
using testing::RunCommand;
using testing::ScratchDir;

TEST(VideoProbeTest, ReadsARealVideosStreamsFrameTimesColoursAndAudio) {
  ASSERT_TRUE(ProgramExists("ffprobe")) << "bash scripts/setup.sh installs ffmpeg";
  const VideoProbe probe = ProbeVideo(DataPath("video/d10.mp4"));
  ASSERT_TRUE(probe.read);
  EXPECT_EQ(probe.streams, 2);
  EXPECT_EQ(probe.video_streams, 1);
  ASSERT_EQ(probe.frame_times.size(), 448u);  // every frame, as OpenCV counts them
  for (std::size_t i = 1; i < probe.frame_times.size(); ++i) {
    ASSERT_NEAR(probe.frame_times[i] - probe.frame_times[i - 1], 1.0 / 30, 1e-3) << i;
  }
  EXPECT_EQ(probe.colour.matrix, "bt709");
  EXPECT_EQ(probe.audio_codec, "aac");
  // Audio and video packets interleave: a handful of audio packets in a row at most.
  EXPECT_GT(probe.longest_run_without_video, 0);
  EXPECT_LT(probe.longest_run_without_video, 10);
}

// ffprobe ends a packet's line with its side data's section, whose fields are
// not the packet's, and writes N/A for a time it does not know.
TEST(VideoProbeTest, ReadsOnlyEachLinesOwnFieldsAndSkipsUnknownTimes) {
  const VideoProbe probe = ParseProbeListing(
      "packet|codec_type=audio|stream_index=1|pts_time=-0.023220|side_data|side_data_type=Skip Samples|codec_type=video\n"
      "packet|codec_type=video|stream_index=0|pts_time=0.066667\n"
      "packet|codec_type=video|stream_index=0|pts_time=0.000000\n"
      "packet|codec_type=video|stream_index=0|pts_time=N/A\n"
      "packet|codec_type=video|stream_index=2|pts_time=0.5\n"
      "packet|codec_type=audio|stream_index=1|pts_time=0.1\n"
      "packet|codec_type=audio|stream_index=1|pts_time=0.2\n"
      "stream|index=0|codec_name=h264|codec_type=video|color_space=bt709|color_transfer=unknown|color_primaries=bt709\n"
      "stream|index=1|codec_name=opus|codec_type=audio\n"
      "stream|index=2|codec_name=mjpeg|codec_type=video|color_space=bt470bg\n"
      "stream|index=3|codec_name=aac|codec_type=audio\n");
  EXPECT_TRUE(probe.read);
  EXPECT_EQ(probe.streams, 4);
  EXPECT_EQ(probe.video_streams, 2);
  EXPECT_EQ(probe.longest_run_without_video, 2);  // the two audio packets at the end; the first is one
  EXPECT_EQ(probe.frame_times, (std::vector<double>{0.0, 0.066667}));  // the first video stream's, sorted
  EXPECT_EQ(probe.colour, (ColourTags{"bt709", "", "bt709"}));
  EXPECT_EQ(probe.audio_codec, "opus");
}

// A command asks once per file, but a file written again is probed again.
TEST(VideoProbeTest, ProbesAFileAgainWhenItChangesAndTellsAudioAlone) {
  ASSERT_TRUE(ProgramExists("ffmpeg") && ProgramExists("ffprobe")) << "bash scripts/setup.sh installs ffmpeg";
  const fs::path dir = ScratchDir("video_probe_changes");
  const fs::path path = dir / "clip.mp4";
  const std::string d10 = Quote(DataPath("video/d10.mp4"));
  ASSERT_EQ(RunCommand("ffmpeg -v error -y -i " + d10 + " -t 0.5 -c copy " + Quote(path)), 0);
  const VideoProbe clip = ProbeVideo(path);
  EXPECT_EQ(clip.video_streams, 1);
  EXPECT_GE(clip.frame_times.size(), 15u);
  EXPECT_NO_THROW(VideoReader{path});

  ASSERT_EQ(RunCommand("ffmpeg -v error -y -i " + d10 + " -t 2 -vn -c copy " + Quote(path)), 0);
  const VideoProbe sound = ProbeVideo(path);
  EXPECT_EQ(sound.streams, 1);
  EXPECT_EQ(sound.video_streams, 0);
  EXPECT_TRUE(sound.frame_times.empty());
  EXPECT_EQ(sound.audio_codec, "aac");
  try {
    VideoReader reader(path);
    ADD_FAILURE() << "an audio file opened as a video";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ExitCode::kBadInput);
    EXPECT_NE(std::string(error.what()).find("holds no video stream"), std::string::npos) << error.what();
  }

  EXPECT_FALSE(ProbeVideo(dir / "missing.mp4").read);
}

}  // namespace
}  // namespace gazedirector
