#include "gazedirector/viz/draw_face.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::DetectStill;

// Pixels of the drawing within a colour range (BGR).
cv::Mat PixelsBetween(const cv::Mat& drawing, const cv::Scalar& low, const cv::Scalar& high) {
  cv::Mat mask;
  cv::inRange(drawing, low, high, mask);
  return mask;
}
// Colours that the photo's skin does not have: the landmark contours' green
// and the head's x axis in red.
const cv::Scalar kGreenLow(0, 150, 0), kGreenHigh(130, 255, 130), kRedLow(0, 0, 180), kRedHigh(90, 90, 255);

double DistanceToNearest(const cv::Point2d& p, const Landmarks68& landmarks) {
  double nearest = 1e9;
  for (const Eigen::Vector2d& l : landmarks) nearest = std::min(nearest, std::hypot(l.x() - p.x, l.y() - p.y));
  return nearest;
}

// The contours join d30's landmarks, and the head's x axis starts at her nose
// and points toward her left, the image's right.
TEST(DrawFaceTest, DrawsTheLandmarksAndTheHeadsAxesWhereTheFaceIs) {
  const testing::DetectedStill still = DetectStill("images/d30.jpg");
  ASSERT_FALSE(still.faces.empty());
  const Face& face = still.faces.front();
  cv::Mat drawing = still.image.clone();
  DrawFace(drawing, face, still.camera);

  const cv::Mat green =
      PixelsBetween(drawing, kGreenLow, kGreenHigh) & ~PixelsBetween(still.image, kGreenLow, kGreenHigh);
  const double eyes_apart = face.InterocularDistance();
  int green_count = 0, green_far = 0;
  for (int y = 0; y < green.rows; ++y) {
    for (int x = 0; x < green.cols; ++x) {
      if (!green.at<uchar>(y, x)) continue;
      ++green_count;
      // Contour points lie on segments between neighbouring landmarks, at
      // most a quarter of the eyes' distance from one (the jaw's spacing).
      green_far += DistanceToNearest(cv::Point2d(x, y), face.landmarks) > 0.25 * eyes_apart;
    }
  }
  EXPECT_GT(green_count, 4 * eyes_apart);
  EXPECT_LT(green_far, 0.01 * green_count);

  const cv::Mat red = PixelsBetween(drawing, kRedLow, kRedHigh) & ~PixelsBetween(still.image, kRedLow, kRedHigh);
  std::vector<cv::Point> red_points;
  cv::findNonZero(red, red_points);
  ASSERT_FALSE(red_points.empty());
  cv::Point2d mean(0, 0);
  for (const cv::Point& p : red_points) mean += cv::Point2d(p);
  mean *= 1.0 / static_cast<double>(red_points.size());
  const Eigen::Vector2d nose = face.landmarks[30];
  // The axis is 40 mm long, about two thirds of the eyes' distance: its
  // middle lies right of the nose tip, at about its height.
  EXPECT_GT(mean.x - nose.x(), 0.15 * eyes_apart);
  EXPECT_LT(mean.x - nose.x(), 0.6 * eyes_apart);
  EXPECT_LT(std::abs(mean.y - nose.y()), 0.2 * eyes_apart);
}

TEST(DrawFaceTest, LinesThickenWithTheImage) {
  EXPECT_EQ(LineThickness(cv::Mat(300, 400, CV_8UC3)), 1);
  EXPECT_EQ(LineThickness(cv::Mat(1080, 1920, CV_8UC3)), 2);
  EXPECT_EQ(LineThickness(cv::Mat(4000, 6000, CV_8UC3)), 10);
}

}  // namespace
}  // namespace gazedirector
