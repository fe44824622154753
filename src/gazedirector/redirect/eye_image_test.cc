#include "gazedirector/redirect/eye_image.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace gazedirector {
namespace {

constexpr float kDark = 0.1f, kLight = 0.9f;

// A dark disc of `radius` about `centre` on light ground, as each pixel's
// share of it would show (16 x 16 samples per pixel).
float DiscCoverageColour(int x, int y, const cv::Point2f& centre, float radius) {
  int inside = 0;
  for (int i = 0; i < 16; ++i) {
    for (int j = 0; j < 16; ++j) {
      inside += std::hypot(x - 0.5f + (i + 0.5f) / 16 - centre.x, y - 0.5f + (j + 0.5f) / 16 - centre.y) < radius;
    }
  }
  const float share = inside / 256.0f;
  return share * kDark + (1 - share) * kLight;
}

// An iris-like disc drawn by pixel centres (as the colour match used to
// switch) comes out as a disc drawn with each pixel's true share of it,
// within a tenth of the contrast, where the hard one was off by up to half.
TEST(EyeImageTest, MixedAcrossEdgeGivesEdgePixelsTheirShareOfEachSide) {
  const cv::Size size(24, 22);
  const cv::Point2f centre(11.3f, 10.6f);
  const float radius = 7.2f;
  cv::Mat hard(size, CV_32FC3), distance(size, CV_32F);
  const cv::Mat mask(size, CV_8UC1, cv::Scalar(255));
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      distance.at<float>(y, x) = std::hypot(x - centre.x, y - centre.y) - radius;
      hard.at<cv::Vec3f>(y, x) = cv::Vec3f::all(distance.at<float>(y, x) > 0 ? kLight : kDark);
    }
  }
  const cv::Mat mixed = MixedAcrossEdge(hard, mask, distance);
  float worst_hard = 0, worst_mixed = 0, sum_hard = 0, sum_mixed = 0;
  int edge = 0;
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      const float truth = DiscCoverageColour(x, y, centre, radius);
      const float hard_error = std::abs(hard.at<cv::Vec3f>(y, x)[0] - truth);
      const float mixed_error = std::abs(mixed.at<cv::Vec3f>(y, x)[0] - truth);
      if (std::abs(distance.at<float>(y, x)) >= 1) {
        EXPECT_EQ(mixed.at<cv::Vec3f>(y, x), hard.at<cv::Vec3f>(y, x)) << x << "," << y;
        continue;
      }
      worst_hard = std::max(worst_hard, hard_error), worst_mixed = std::max(worst_mixed, mixed_error);
      sum_hard += hard_error, sum_mixed += mixed_error, ++edge;
    }
  }
  std::printf("%d pixels by the edge: error mean %.3f worst %.3f (per-pixel choice: %.3f, %.3f)\n", edge,
              sum_mixed / edge, worst_mixed, sum_hard / edge, worst_hard);
  EXPECT_GT(edge, 60);
  EXPECT_LT(sum_mixed / edge, 0.5f * sum_hard / edge);
  EXPECT_LT(worst_mixed, 0.1f * (kLight - kDark) + 0.05f);
}

// Pixels outside the mask are neither changed nor mixed into their neighbours.
TEST(EyeImageTest, MixedAcrossEdgeStaysWithinTheMask) {
  const cv::Size size(6, 1);
  cv::Mat image(size, CV_32FC3), distance(size, CV_32F);
  cv::Mat mask(size, CV_8UC1, cv::Scalar(255));
  for (int x = 0; x < size.width; ++x) {
    distance.at<float>(0, x) = x - 2.8f;  // the edge between pixels 2 and 3, nearer 3
    image.at<cv::Vec3f>(0, x) = cv::Vec3f::all(x < 3 ? kDark : kLight);
  }
  cv::Mat mixed = MixedAcrossEdge(image, mask, distance);
  EXPECT_NEAR(mixed.at<cv::Vec3f>(0, 2)[0], kDark, 1e-6f);  // 0.8 of a pixel inside: all dark
  EXPECT_NEAR(mixed.at<cv::Vec3f>(0, 3)[0], 0.7f * kLight + 0.3f * kDark, 1e-6f);
  mask.at<uchar>(0, 2) = 0;
  mixed = MixedAcrossEdge(image, mask, distance);
  EXPECT_EQ(mixed.at<cv::Vec3f>(0, 3), image.at<cv::Vec3f>(0, 3));
  EXPECT_EQ(mixed.at<cv::Vec3f>(0, 2), image.at<cv::Vec3f>(0, 2));
}

// Computed around the mask only, the depth is the whole image's transform,
// also where the mask meets the image's edge (no outside pixel there).
TEST(EyeImageTest, DepthInsideIsTheWholeImagesDistanceTransform) {
  cv::Mat mask(60, 90, CV_8UC1, cv::Scalar(0));
  cv::ellipse(mask, cv::Point(8, 30), cv::Size(14, 9), 10, 0, 360, cv::Scalar(255), cv::FILLED);
  cv::ellipse(mask, cv::Point(55, 28), cv::Size(16, 7), -5, 0, 360, cv::Scalar(255), cv::FILLED);
  mask.at<uchar>(50, 80) = 255;
  cv::Mat whole;
  cv::distanceTransform(mask, whole, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const cv::Mat depth = DepthInside(mask);
  ASSERT_EQ(depth.type(), CV_32F);
  EXPECT_EQ(cv::norm(depth, whole, cv::NORM_INF), 0.0);
  EXPECT_GT(depth.at<float>(30, 0), 5.0f);  // the image's edge is no outside pixel
  EXPECT_EQ(cv::countNonZero(DepthInside(cv::Mat(mask.size(), CV_8UC1, cv::Scalar(0)))), 0);
}

}  // namespace
}  // namespace gazedirector
