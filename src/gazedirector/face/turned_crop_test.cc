#include "gazedirector/face/turned_crop.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "gazedirector/geometry/rotation.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

TEST(TurnedCropTest, MapsBetweenImageAndCropBothWays) {
  const TurnedCrop crop{{250.5, 180.0}, DegToRad(35.0), 0.6, {201, 151}};
  const Eigen::Vector2d centre = crop.ToImage({100.0, 75.0});
  EXPECT_NEAR(centre.x(), 250.5, 1e-9);
  EXPECT_NEAR(centre.y(), 180.0, 1e-9);
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(0, 0), Eigen::Vector2d(312.25, -40), Eigen::Vector2d(-7, 999)}) {
    EXPECT_LT((crop.ToImage(crop.ToCrop(p)) - p).norm(), 1e-9);
  }
  // The crop's x axis runs along the roll, clockwise as shown, at 1 / scale.
  const Eigen::Vector2d step = crop.ToImage({101.0, 75.0}) - centre;
  EXPECT_NEAR(std::atan2(step.y(), step.x()), DegToRad(35.0), 1e-9);
  EXPECT_NEAR(step.norm(), 1 / 0.6, 1e-9);
}

TEST(TurnedCropTest, CentresACropOnABoxThatStandsUprightInIt) {
  const cv::Rect2d box(40.0, 60.0, 120.0, 100.0);
  const TurnedCrop crop = TurnedCrop::AroundBox(box, DegToRad(-70.0), 0.5, 2.0);
  EXPECT_EQ(crop.size, cv::Size(120, 120));
  const cv::Rect2d inside = crop.BoxInCrop(box);
  EXPECT_NEAR(inside.x + 0.5 * inside.width, 59.5, 1e-9);
  EXPECT_NEAR(inside.y + 0.5 * inside.height, 59.5, 1e-9);
  EXPECT_NEAR(inside.width, 60.0, 1e-9);
  EXPECT_NEAR(inside.height, 50.0, 1e-9);
}

TEST(TurnedCropTest, CutsThePixelsItMapsTo) {
  const cv::Mat gray = testing::GrayPhoto("images/s42.jpg");
  const TurnedCrop crop = TurnedCrop::WholeImage(gray.size(), DegToRad(-60.0), 1.0);
  const cv::Mat cut = crop.Cut(gray, cv::BORDER_CONSTANT);
  ASSERT_EQ(cut.size(), crop.size);
  // Every corner of the photo lies inside the cut.
  for (const Eigen::Vector2d& corner : {Eigen::Vector2d(0, 0), Eigen::Vector2d(gray.cols - 1, 0),
                                        Eigen::Vector2d(0, gray.rows - 1), Eigen::Vector2d(gray.cols - 1, gray.rows - 1)}) {
    const Eigen::Vector2d q = crop.ToCrop(corner);
    EXPECT_GE(q.x(), -0.5);
    EXPECT_GE(q.y(), -0.5);
    EXPECT_LE(q.x(), crop.size.width - 0.5);
    EXPECT_LE(q.y(), crop.size.height - 0.5);
  }
  // A cut pixel is the photo's pixel it maps to (bilinear, so against the
  // photo sampled the same way).
  int compared = 0;
  double error = 0;
  for (int y = 40; y < cut.rows - 40; y += 37) {
    for (int x = 40; x < cut.cols - 40; x += 41) {
      const Eigen::Vector2d p = crop.ToImage({double(x), double(y)});
      if (p.x() < 1 || p.y() < 1 || p.x() > gray.cols - 2 || p.y() > gray.rows - 2) continue;
      cv::Mat sample;
      cv::getRectSubPix(gray, {1, 1}, cv::Point2f(static_cast<float>(p.x()), static_cast<float>(p.y())), sample);
      error += std::abs(double(cut.at<uchar>(y, x)) - sample.at<uchar>(0, 0));
      ++compared;
    }
  }
  ASSERT_GT(compared, 50);
  EXPECT_LT(error / compared, 1.0);
}

TEST(TurnedCropTest, ReadsTheRollFromTheEyes) {
  const testing::DetectedStill still = testing::DetectStill("images/s42.jpg");
  ASSERT_EQ(still.faces.size(), 1u);
  const double upright = LandmarkRoll(still.faces[0].landmarks);
  EXPECT_LT(std::abs(upright), DegToRad(10.0));
  for (double turn : {30.0, 100.0, -150.0}) {
    const testing::TurnedPhoto turned = testing::TurnPhoto(still.image, turn);
    EXPECT_NEAR(AngleDifference(LandmarkRoll(turned.Map(still.faces[0].landmarks)), upright), DegToRad(turn), 1e-6) << turn;
  }
  EXPECT_NEAR(AngleDifference(DegToRad(170.0), DegToRad(-170.0)), DegToRad(-20.0), 1e-12);
  EXPECT_NEAR(AngleDifference(DegToRad(-170.0), DegToRad(170.0)), DegToRad(20.0), 1e-12);
}

}  // namespace
}  // namespace gazedirector
