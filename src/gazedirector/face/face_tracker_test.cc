#include "gazedirector/face/face_tracker.h"

#include <gtest/gtest.h>

#include "gazedirector/eval/landmark_accuracy.h"
#include "gazedirector/face/turned_crop.h"
#include "gazedirector/geometry/rotation.h"
#include "gazedirector/io/image_io.h"
#include "gazedirector/io/video_reader.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::DataPath;

using testing::MakeFaceTracker;

std::vector<cv::Mat> ReadFrames(const std::string& video, int count) {
  VideoReader reader(DataPath(video));
  std::vector<cv::Mat> frames;
  cv::Mat frame;
  while (static_cast<int>(frames.size()) < count && reader.Read(frame)) frames.push_back(frame.clone());
  return frames;
}

// The faces a fresh tracker finds in one of the real photos, with the default camera.
std::vector<Face> FacesIn(const std::string& photo) { return testing::DetectStill(photo).faces; }

TEST(FaceTrackerTest, FindsTheFaceInAPortraitAndNoneInACat) {
  const std::vector<Face> faces = FacesIn("images/s42.jpg");
  ASSERT_EQ(faces.size(), 1u);
  EXPECT_GT(faces[0].confidence, 0.9);
  EXPECT_GT(faces[0].InterocularDistance(), 60);
  // A roughly frontal face 30-70 cm from a camera with the default intrinsics.
  EXPECT_GT(faces[0].pose.translation.z(), 300);
  EXPECT_LT(faces[0].pose.translation.z(), 700);
  EXPECT_GT(faces[0].pose.rotation(2, 2), std::cos(0.35));

  EXPECT_TRUE(FacesIn("images/s39.jpg").empty());
}

TEST(FaceTrackerTest, FindsAFaceThatHogScoresLowAsAWeakDetection) {
  // Glasses, a frown and hair over the brows: HOG's best window scores below 0.
  const std::vector<Face> faces = FacesIn("images/d8.jpg");
  ASSERT_EQ(faces.size(), 1u);
  EXPECT_LT(faces[0].confidence, 0.5);
  // The eyes sit in the upper half of the face box, level with each other.
  const cv::Rect2d box = faces[0].box;
  for (int i : {36, 39, 42, 45}) {
    EXPECT_TRUE(box.contains(cv::Point2d(faces[0].landmarks[i].x(), faces[0].landmarks[i].y()))) << i;
    EXPECT_LT(faces[0].landmarks[i].y(), box.y + 0.55 * box.height) << i;
  }
  EXPECT_LT(std::abs(faces[0].landmarks[36].y() - faces[0].landmarks[45].y()), 0.1 * faces[0].InterocularDistance());
}

// A head leaning over or a camera held askew: HOG finds upright faces to
// about 30-40 degrees of tilt, the upright landmark predictor less far.
TEST(FaceTrackerTest, FindsAndLandmarksFacesTiltedInThePhotoAtAnyAngle) {
  const testing::DetectedStill still = testing::DetectStill("images/s12.jpg");
  ASSERT_EQ(still.faces.size(), 1u);
  const Face& upright = still.faces[0];
  EXPECT_EQ(upright.box_roll, 0.0);
  for (double turn : {30.0, -45.0, 60.0, 90.0, -100.0, 140.0, 180.0}) {
    const testing::TurnedPhoto turned = testing::TurnPhoto(still.image, turn);
    const std::vector<Face> faces =
        MakeFaceTracker().DetectFaces(turned.image, Camera::Default(turned.image.cols, turned.image.rows));
    ASSERT_EQ(faces.size(), 1u) << turn;
    EXPECT_GT(faces[0].confidence, 0.5) << turn;
    EXPECT_LT(NormalisedLandmarkError(faces[0].landmarks, turned.Map(upright.landmarks)), 0.02) << turn;  // measured 0.010
    // The box stands upright to the face (within the tolerance a landmark
    // roll is taken at, or upright where the predictor reads the face as is).
    const double tilt = LandmarkRoll(faces[0].landmarks);
    if (faces[0].box_roll != 0) {
      EXPECT_LT(std::abs(AngleDifference(faces[0].box_roll, tilt)), DegToRad(5.5)) << turn;
    }
    if (std::abs(turn) >= 45) {
      EXPECT_NE(faces[0].box_roll, 0.0) << turn;
    }
  }
}

TEST(FaceTrackerTest, FindsEveryFaceInAGroupPhotoAndLargestPicksOne) {
  const cv::Mat group = ReadImage(DataPath("dlib-faces/bald_guys.jpg"));
  const Camera camera = Camera::Default(group.cols, group.rows);
  FaceTracker all = MakeFaceTracker();
  const std::vector<Face> faces = all.DetectFaces(group, camera);
  ASSERT_GE(faces.size(), 3u);
  for (std::size_t i = 1; i < faces.size(); ++i) EXPECT_LE(faces[i - 1].box.x, faces[i].box.x) << "ids go left to right";

  FaceTrackerOptions largest_only;
  largest_only.largest_only = true;
  FaceTracker largest = MakeFaceTracker(largest_only);
  const std::vector<Face> one = largest.DetectFaces(group, camera);
  ASSERT_EQ(one.size(), 1u);
  for (const Face& face : faces) EXPECT_LE(face.box.area(), one[0].box.area() + 1e-6);
}

TEST(FaceTrackerTest, TracksAVideoFaceWithAStableIdAndWithoutDrift) {
  const std::vector<cv::Mat> frames = ReadFrames("video/d3.mp4", 120);
  ASSERT_EQ(frames.size(), 120u);
  const Camera camera = Camera::Default(frames[0].cols, frames[0].rows);
  FaceTracker tracker = MakeFaceTracker();
  FaceTracker still = MakeFaceTracker();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::vector<Face> faces = tracker.TrackFrame(frames[i], i / 30.0, camera);
    ASSERT_EQ(faces.size(), 1u) << "frame " << i;
    EXPECT_EQ(faces[0].id, 0);
    if (i % 30 == 29) {
      // Tracked landmarks stay close to a fresh detection of the same frame.
      const std::vector<Face> fresh = still.DetectFaces(frames[i], camera);
      ASSERT_EQ(fresh.size(), 1u);
      double error = 0;
      for (int k = 0; k < kNumLandmarks; ++k) error += (faces[0].landmarks[k] - fresh[0].landmarks[k]).norm();
      EXPECT_LT(error / kNumLandmarks, 0.05 * fresh[0].InterocularDistance()) << "frame " << i;
    }
  }
}

// A face that tilts over in a video, a quarter turn in two seconds, stays one
// track: each frame is landmarked in a crop turned upright to its last tilt,
// and the detector's check looks there too.
TEST(FaceTrackerTest, FollowsAFaceThatTiltsOverInAVideo) {
  const std::vector<cv::Mat> frames = ReadFrames("video/d19.mp4", 75);
  ASSERT_EQ(frames.size(), 75u);
  FaceTracker tracker = MakeFaceTracker();
  FaceTracker still = MakeFaceTracker();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const double turn = 90.0 * std::min(1.0, i / 60.0);
    const testing::TurnedPhoto turned = testing::TurnPhoto(frames[i], turn);
    const Camera camera = Camera::Default(turned.image.cols, turned.image.rows);
    const std::vector<Face> faces = tracker.TrackFrame(turned.image, i / 30.0, camera);
    ASSERT_EQ(faces.size(), 1u) << "frame " << i;
    EXPECT_EQ(faces[0].id, 0) << "frame " << i;
    EXPECT_GT(faces[0].confidence, 0.5) << "frame " << i;
    if (i % 15 == 14) {
      const Camera upright_camera = Camera::Default(frames[i].cols, frames[i].rows);
      const std::vector<Face> fresh = still.DetectFaces(frames[i], upright_camera);
      ASSERT_EQ(fresh.size(), 1u);
      // Measured 0.009-0.032, the most while it turns 1.5 degrees a frame.
      EXPECT_LT(NormalisedLandmarkError(faces[0].landmarks, turned.Map(fresh[0].landmarks)), 0.05) << "frame " << i;
    }
  }
}

TEST(FaceTrackerTest, SmoothingRemovesJitterWithoutLagging) {
  const std::vector<cv::Mat> frames = ReadFrames("video/d19.mp4", 150);
  const Camera camera = Camera::Default(frames[0].cols, frames[0].rows);
  FaceTrackerOptions raw_options;
  raw_options.smooth = false;
  FaceTracker raw_tracker = MakeFaceTracker(raw_options);
  FaceTracker smooth_tracker = MakeFaceTracker();
  std::vector<Landmarks68> raw, smooth;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    raw.push_back(raw_tracker.TrackFrame(frames[i], i / 30.0, camera).at(0).landmarks);
    smooth.push_back(smooth_tracker.TrackFrame(frames[i], i / 30.0, camera).at(0).landmarks);
  }
  // Jitter: the frame-to-frame second difference; lag: the mean distance
  // between smoothed and raw points. Both relative to the eye-corner distance.
  double raw_jitter = 0, smooth_jitter = 0, offset = 0;
  const double unit = (raw[0][45] - raw[0][36]).norm();
  for (std::size_t i = 2; i < frames.size(); ++i) {
    for (int k = 0; k < kNumLandmarks; ++k) {
      raw_jitter += (raw[i][k] - 2 * raw[i - 1][k] + raw[i - 2][k]).norm();
      smooth_jitter += (smooth[i][k] - 2 * smooth[i - 1][k] + smooth[i - 2][k]).norm();
      offset += (smooth[i][k] - raw[i][k]).norm();
    }
  }
  const double samples = (frames.size() - 2) * kNumLandmarks;
  EXPECT_LT(smooth_jitter, 0.6 * raw_jitter);
  EXPECT_LT(offset / samples / unit, 0.02);
}

TEST(FaceTrackerTest, DropsALostFaceAndFindsTheNextWithANewId) {
  std::vector<cv::Mat> frames = ReadFrames("video/d3.mp4", 10);
  const cv::Mat blank(frames[0].size(), CV_8UC3, cv::Scalar(40, 40, 40));
  for (int i = 0; i < 10; ++i) frames.push_back(blank);
  for (const cv::Mat& frame : ReadFrames("video/d19.mp4", 10)) {
    cv::Mat padded;
    cv::copyMakeBorder(frame, padded, 0, 32, 0, 32, cv::BORDER_REPLICATE);
    frames.push_back(padded);
  }
  const Camera camera = Camera::Default(frames[0].cols, frames[0].rows);
  FaceTracker tracker = MakeFaceTracker();
  std::vector<std::size_t> counts;
  std::vector<int> ids;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::vector<Face> faces = tracker.TrackFrame(frames[i], i / 30.0, camera);
    counts.push_back(faces.size());
    ids.push_back(faces.empty() ? -1 : faces[0].id);
  }
  EXPECT_EQ(counts[5], 1u);
  EXPECT_EQ(ids[5], 0);
  EXPECT_EQ(counts[19], 0u) << "the face is dropped once the detector stops seeing it";
  EXPECT_EQ(counts[29], 1u);
  EXPECT_EQ(ids[29], 1) << "a face found anew gets a new id";
}

}  // namespace
}  // namespace gazedirector
