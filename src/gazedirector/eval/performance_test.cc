// What the benchmarks measure on, not how fast it is: speed targets are
// printed by `gazedirector bench`, never asserted.
#include "gazedirector/eval/performance.h"

#include <gtest/gtest.h>

#include "gazedirector/io/video_reader.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::DataPath;
using testing::SharedModel;

// A clip keeps each frame it decoded (its own copy, not the reader's buffer)
// with the face tracked in it.
TEST(PerformanceTest, ATrackedClipKeepsEachFrameWithItsFace) {
  FaceTracker tracker = testing::MakeFaceTracker();
  const TrackedClip clip = LoadTrackedClip(DataPath("video/d3.mp4"), tracker, 4);
  ASSERT_EQ(clip.frames.size(), 4u);
  ASSERT_EQ(clip.faces.size(), 4u);

  VideoReader reader(DataPath("video/d3.mp4"));
  EXPECT_EQ(clip.camera.width, reader.info().width);
  EXPECT_EQ(clip.camera.height, reader.info().height);
  cv::Mat first;
  ASSERT_TRUE(reader.Read(first));
  EXPECT_EQ(cv::norm(clip.frames[0], first, cv::NORM_INF), 0);  // d3 shows its face from the first frame
  EXPECT_GT(cv::norm(clip.frames[0], clip.frames[3], cv::NORM_L1), 0);
  const cv::Rect2d frame_area(0, 0, clip.camera.width, clip.camera.height);
  for (const Face& face : clip.faces) {
    EXPECT_GE(face.confidence, 0.5);
    EXPECT_GT(face.InterocularDistance(), 20);
    for (const Eigen::Vector2d& point : face.landmarks) {
      EXPECT_TRUE(frame_area.contains(cv::Point2d(point.x(), point.y()))) << point.transpose();
    }
  }
  // The face moves little between neighbouring frames of a talking head.
  EXPECT_LT((clip.faces[0].landmarks[30] - clip.faces[1].landmarks[30]).norm(), 10);
}

TEST(PerformanceTest, TooShortAClipMeasuresNothing) {
  FaceTracker tracker = testing::MakeFaceTracker();
  const TrackedClip one = LoadTrackedClip(DataPath("video/d3.mp4"), tracker, 1);
  ASSERT_EQ(one.frames.size(), 1u);
  EXPECT_EQ(MeasureFitFps(SharedModel(), one), 0);  // no warm-started fit to time
  EXPECT_EQ(MeasureRedirectFps(SharedModel(), TrackedClip{one.camera, {}, {}}), 0);
}

}  // namespace
}  // namespace gazedirector
