#include "gazedirector/redirect/eyeball_transfer.h"

#include <gtest/gtest.h>

namespace gazedirector {
namespace {

// A hole's pixel takes the carried pixel nearest to it: by Euclidean
// distance, not by the square ring it lies on.
TEST(NearestCarriedTest, FindsTheNearestCarriedPixel) {
  cv::Mat carried(20, 20, CV_8UC1, cv::Scalar(0));
  carried.at<uchar>(10, 14) = 255;  // 4 to the right
  carried.at<uchar>(13, 13) = 255;  // 3 down and 3 to the right: the same ring, farther (4.24)
  carried.at<uchar>(6, 10) = 255;   // 4 up: as near as the first
  const cv::Point nearest = NearestCarried(carried, {10, 10}, 10);
  EXPECT_DOUBLE_EQ(cv::norm(nearest - cv::Point(10, 10)), 4.0) << nearest;
  carried.at<uchar>(12, 12) = 255;  // 2.83 away, on a nearer ring
  EXPECT_EQ(NearestCarried(carried, {10, 10}, 10), cv::Point(12, 12));
  carried.at<uchar>(11, 10) = 255;
  EXPECT_EQ(NearestCarried(carried, {10, 10}, 10), cv::Point(10, 11));
}

TEST(NearestCarriedTest, LooksNoFurtherThanItsReachNorOutsideTheImage) {
  cv::Mat carried(20, 20, CV_8UC1, cv::Scalar(0));
  carried.at<uchar>(0, 19) = 255;
  EXPECT_EQ(NearestCarried(carried, {2, 2}, 5), cv::Point(2, 2));  // none within 5: itself
  EXPECT_EQ(NearestCarried(carried, {2, 2}, 30), cv::Point(19, 0));
  EXPECT_EQ(NearestCarried(carried, {19, 19}, 30), cv::Point(19, 0));  // its rings run off the image
}

}  // namespace
}  // namespace gazedirector
