#include "gazedirector/io/video_reader.h"

#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "gazedirector/util/subprocess.h"
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

}  // namespace
}  // namespace gazedirector
