#include "gazedirector/io/video_reader.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "gazedirector/util/subprocess.h"
#include "gazedirector/util/temporary_folder.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;
using testing::DataPath;
using testing::Quote;
using testing::RunCommand;
using testing::ScratchDir;

TEST(VideoReaderTest, ReadsARealVideosSizeRateAndEveryFrame) {
  VideoReader reader(DataPath("video/s18.mp4"));
  EXPECT_EQ(reader.info().width, 1280);
  EXPECT_EQ(reader.info().height, 720);
  EXPECT_NEAR(reader.info().frame_rate.value(), 30.0, 1e-9);
  cv::Mat frame;
  long frames = 0;
  while (reader.Read(frame)) {
    ASSERT_EQ(frame.type(), CV_8UC3);
    ASSERT_EQ(frame.cols, 1280);
    ++frames;
  }
  EXPECT_EQ(frames, reader.info().frame_count);
  EXPECT_FALSE(reader.EndedEarly());
}

// A phone stores its frames as the sensor saw them and asks players to turn
// them; the reader must show them as ffmpeg (and so every player) does.
TEST(VideoReaderTest, TurnsFramesAsTheContainerAsksLikeFfmpeg) {
  ASSERT_TRUE(ProgramExists("ffmpeg")) << "bash scripts/setup.sh installs ffmpeg";
  const fs::path dir = ScratchDir("video_reader_rotation");
  for (const int rotate : {90, 180, 270}) {
    const fs::path video = dir / ("rotate" + std::to_string(rotate) + ".mp4");
    const fs::path shown = dir / ("rotate" + std::to_string(rotate) + ".png");
    ASSERT_EQ(RunCommand("ffmpeg -v error -y -i " + Quote(DataPath("video/s18.mp4")) + " -t 0.5 -c copy -metadata:s:v:0 rotate=" +
                    std::to_string(rotate) + " " + Quote(video)),
              0);
    ASSERT_EQ(RunCommand("ffmpeg -v error -y -i " + Quote(video) + " -frames:v 1 " + Quote(shown)), 0);
    const cv::Mat expected = cv::imread(shown.string());
    ASSERT_FALSE(expected.empty());

    VideoReader reader(video);
    EXPECT_EQ(reader.info().width, expected.cols) << rotate;
    EXPECT_EQ(reader.info().height, expected.rows) << rotate;
    cv::Mat frame;
    ASSERT_TRUE(reader.Read(frame));
    ASSERT_EQ(frame.size(), expected.size()) << rotate;
    // The same decoded picture up to the colour conversion's rounding; a wrong turn differs by tens of levels.
    EXPECT_LT(cv::norm(frame, expected, cv::NORM_L1) / frame.total() / 3, 3.0) << rotate;
  }
}

// Phones and screen recorders write variable-rate videos: frames must keep
// their own times, and a writer needs a rate on which none is dropped.
TEST(VideoReaderTest, ReadsAVariableRateVideosFramesAtTheirOwnTimes) {
  ASSERT_TRUE(ProgramExists("ffmpeg")) << "bash scripts/setup.sh installs ffmpeg";
  const fs::path video = ScratchDir("video_reader_vfr") / "vfr.mp4";
  // s18 at 30 fps: every 3rd frame of the first second, all of the second, every 3rd of the third.
  ASSERT_EQ(testing::WriteSelectedFrames("video/s18.mp4", 3, "not(mod(n,3))+between(n,30,59)", video), 0);
  VideoReader reader(video);
  std::vector<double> times;
  cv::Mat frame;
  while (reader.Read(frame)) times.push_back(reader.timestamp_s());
  ASSERT_EQ(times.size(), 10u + 30u + 10u);
  for (std::size_t i = 0; i < times.size(); ++i) {
    const long source_frame = i < 10 ? 3 * i : i < 40 ? 30 + (i - 10) : 60 + 3 * (i - 40);
    EXPECT_NEAR(times[i], source_frame / 30.0, 1e-3) << i;
  }
  EXPECT_NEAR(SteadyFrameRate(video, reader.info()).value(), 30.0, 1e-9);
  EXPECT_NEAR(reader.info().frame_rate.value(), 50 / 2.933, 0.1);  // the stated rate is the average

  VideoReader steady(DataPath("video/s18.mp4"));
  EXPECT_NEAR(SteadyFrameRate(DataPath("video/s18.mp4"), steady.info()).value(), 30.0, 1e-9);
  long index = 0;
  while (steady.Read(frame) && index < 100) EXPECT_NEAR(steady.timestamp_s(), index++ / 30.0, 1e-6);
}

// A screen recording idles at a frame a second between bursts: writing it at
// its bursts' rate would repeat each frame dozens of times, so the rate is
// held to four frames written per frame read on average.
TEST(VideoReaderTest, ASparseVideosSteadyRateIsHeldToFourTimesItsAverage) {
  ASSERT_TRUE(ProgramExists("ffmpeg")) << "bash scripts/setup.sh installs ffmpeg";
  const fs::path video = ScratchDir("video_reader_sparse") / "sparse.mp4";
  // s18 at 30 fps: one frame a second for 8 s, with a burst of every frame from 3 s to 4 s.
  ASSERT_EQ(testing::WriteSelectedFrames("video/s18.mp4", 8, "not(mod(n,30))+between(n,91,119)", video), 0);
  VideoReader reader(video);
  const double average = (8 + 29 - 1) / 7.0;  // 37 frames from 0 s to 7 s
  const FrameRate steady = SteadyFrameRate(video, reader.info());
  EXPECT_EQ(steady.denominator, 1);
  EXPECT_EQ(steady.numerator, static_cast<int>(4 * average));
}

// OpenCV's reader stops after 512 packets of other streams in a row, which
// lost the last frames of a video whose audio runs on well past them (three of
// ten here for H.264, one for VP9), and every frame after one held on screen
// that long. Such a video is read from a copy of its video stream, which keeps
// the frames' turn and times and is removed after.
TEST(VideoReaderTest, ReadsEveryFrameOfAVideoWhoseAudioOutlastsIt) {
  ASSERT_TRUE(ProgramExists("ffmpeg")) << "bash scripts/setup.sh installs ffmpeg";
  const fs::path dir = ScratchDir("video_reader_long_audio");
  // The copies go to /tmp where $TMPDIR names no folder (it made the reader fail).
  const testing::ScopedEnv tmpdir("TMPDIR", (dir / "no such folder").string());
  const auto copies_left = [] {
    long copies = 0;
    for (const auto& entry : fs::directory_iterator(TemporaryFolder())) {
      const std::string name = entry.path().filename().string();
      copies += name.rfind("gazedirector-", 0) == 0 && name.find("-video.") != std::string::npos;
    }
    return copies;
  };
  const long copies_before = copies_left();
  const std::string d10 = Quote(DataPath("video/d10.mp4"));
  const struct {
    std::string name, video_codec, audio_codec;
    int rotate;
  } videos[] = {{"h264.mp4", "libx264", "copy", 90}, {"vp9.webm", "libvpx-vp9 -deadline realtime", "libopus", 0}};
  for (const auto& video : videos) {
    const fs::path path = dir / video.name, frames = dir / ("frames_" + video.name);
    // Ten frames of d10 (a third of a second) with all 15 s of its sound.
    ASSERT_EQ(RunCommand("ffmpeg -v error -y -i " + d10 + " -an -frames:v 10 -c:v " + video.video_codec + " " +
                         Quote(frames) + " && ffmpeg -v error -y -i " + Quote(frames) + " -i " + d10 +
                         " -map 0:v -map 1:a -c:v copy -c:a " + video.audio_codec + " -metadata:s:v:0 rotate=" +
                         std::to_string(video.rotate) + " " + Quote(path) + " && ffmpeg -v error -y -i " + Quote(path) +
                         " -frames:v 1 " + Quote(dir / "first.png")),
              0)
        << video.name;
    const cv::Mat expected = cv::imread((dir / "first.png").string());
    VideoReader reader(path);
    cv::Mat frame, first;
    std::vector<double> times;
    while (reader.Read(frame)) {
      if (times.empty()) first = frame.clone();
      times.push_back(reader.timestamp_s());
    }
    ASSERT_EQ(times.size(), 10u) << video.name;
    for (std::size_t i = 0; i < times.size(); ++i) EXPECT_NEAR(times[i], i / 30.0, 2e-3) << video.name << " " << i;
    EXPECT_FALSE(reader.EndedEarly()) << video.name;
    EXPECT_NEAR(reader.info().frame_count, 10, 1) << video.name;
    ASSERT_EQ(first.size(), expected.size()) << video.name;
    EXPECT_LT(cv::norm(first, expected, cv::NORM_L1) / first.total() / 3, 3.0) << video.name;
  }
  // The same where a frame stays on screen for 13.7 s mid-video: ten frames, then ten more 14 s in.
  const fs::path frozen = dir / "frozen.mp4";
  ASSERT_EQ(RunCommand("ffmpeg -v error -y -i " + d10 + " -i " + d10 +
                       " -map 0:v -map 1:a -vf \"select='lt(n,10)+between(n,420,429)',setpts='if(lt(N,10),N,N+410)/30/TB'\""
                       " -fps_mode vfr -c:v libx264 -c:a copy " + Quote(frozen)),
            0);
  std::vector<double> times;
  {
    VideoReader reader(frozen);
    cv::Mat frame;
    while (reader.Read(frame)) times.push_back(reader.timestamp_s());
  }
  ASSERT_EQ(times.size(), 20u);
  for (std::size_t i = 0; i < times.size(); ++i) EXPECT_NEAR(times[i], (i < 10 ? i : i + 410) / 30.0, 2e-3) << i;
  EXPECT_EQ(copies_left(), copies_before);
}

}  // namespace
}  // namespace gazedirector
