#include "gazedirector/video/tracked_frame_reader.h"

#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "gazedirector/util/error.h"
#include "gazedirector/util/subprocess.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;

GazeTracker MakeGazeTracker() {
  return GazeTracker(testing::SharedModel(), testing::SharedLandmarkDetector(), testing::SharedMeanFace());
}

// Reading and tracking ahead changes nothing: d14.mp4's first frames, their
// faces and fits are those of ProcessFrame in turn, to the bit.
TEST(TrackedFrameReaderTest, GivesTheFramesFacesAndFitsOfReadingAndTrackingInTurn) {
  const fs::path video = testing::DataPath("video/d14.mp4");
  VideoReader in_turn_reader(video), ahead_reader(video);
  const Camera camera = Camera::Default(in_turn_reader.info().width, in_turn_reader.info().height);
  GazeTracker in_turn = MakeGazeTracker(), ahead = MakeGazeTracker();
  TrackedFrameReader tracked_frames(ahead_reader, ahead, camera);
  cv::Mat expected;
  TrackedFrame frame;
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(in_turn_reader.Read(expected));
    ASSERT_TRUE(tracked_frames.Next(frame));
    const std::vector<FaceFit> expected_fits = in_turn.ProcessFrame(expected, in_turn_reader.timestamp_s(), camera);
    const std::vector<FaceFit> fits = ahead.FitFaces(frame.image, frame.timestamp_s, camera, frame.faces);
    EXPECT_EQ(frame.index, i);
    EXPECT_EQ(frame.timestamp_s, in_turn_reader.timestamp_s()) << i;
    ASSERT_EQ(frame.image.size(), expected.size());
    EXPECT_EQ(cv::norm(frame.image, expected, cv::NORM_INF), 0) << i;
    ASSERT_EQ(fits.size(), 1u) << i;
    ASSERT_EQ(expected_fits.size(), 1u) << i;
    EXPECT_EQ(fits[0].face.landmarks, expected_fits[0].face.landmarks) << i;
    EXPECT_EQ(fits[0].fit.phi.values, expected_fits[0].fit.phi.values) << i;
    EXPECT_EQ(fits[0].fit.terms.total(), expected_fits[0].fit.terms.total()) << i;
  }
}

TEST(TrackedFrameReaderTest, EndsWithTheVideoAndPassesOnWhatReadingThrew) {
  ASSERT_TRUE(ProgramExists("ffmpeg")) << "bash scripts/setup.sh installs ffmpeg";
  const fs::path dir = testing::ScratchDir("tracked_frame_reader");
  const fs::path clip = dir / "clip.mp4";
  ASSERT_EQ(testing::RunCommand("ffmpeg -v error -y -i " + testing::Quote(testing::DataPath("video/d14.mp4")) +
                                " -frames:v 3 -an -c:v libx264 -movflags +faststart " + testing::Quote(clip)),
            0);
  {
    VideoReader reader(clip);
    GazeTracker tracker = MakeGazeTracker();
    TrackedFrameReader tracked_frames(reader, tracker, Camera::Default(reader.info().width, reader.info().height));
    TrackedFrame frame;
    int frames = 0;
    while (tracked_frames.Next(frame)) ++frames;
    EXPECT_EQ(frames, 3);
    EXPECT_FALSE(tracked_frames.Next(frame));  // and stays ended
    EXPECT_EQ(reader.frame_index(), 2);
    EXPECT_FALSE(reader.EndedEarly());
  }

  // The same clip cut off a little way into its frames' data: it opens, and
  // no frame decodes, which the reading thread reports.
  std::ifstream whole(clip, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(whole)), std::istreambuf_iterator<char>());
  const std::size_t data = bytes.find("mdat");
  ASSERT_NE(data, std::string::npos);
  const fs::path cut = dir / "cut.mp4";
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, data + 200);
  VideoReader reader(cut);
  GazeTracker tracker = MakeGazeTracker();
  TrackedFrameReader tracked_frames(reader, tracker, Camera::Default(reader.info().width, reader.info().height));
  TrackedFrame frame;
  try {
    tracked_frames.Next(frame);
    ADD_FAILURE() << "a video whose frames cannot be decoded gave a frame";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ExitCode::kBadInput);
    EXPECT_NE(std::string(error.what()).find("no frame could be decoded"), std::string::npos) << error.what();
  }
  EXPECT_FALSE(tracked_frames.Next(frame));
}

}  // namespace
}  // namespace gazedirector
