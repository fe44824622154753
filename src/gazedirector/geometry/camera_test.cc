#include "gazedirector/geometry/camera.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace gazedirector {
namespace {

// A region resized as the fitter resizes it: a point projects through the
// resampled camera where ToResampled puts its projection through the
// original, and cv::resize puts the original pixel's value there. An image
// that is linear in x and y is reproduced exactly by INTER_LINEAR, so its
// value names the original coordinates it was sampled from.
TEST(CameraTest, TheResampledCameraFollowsCvResize) {
  const Camera camera = Camera::Default(640, 480);
  const int x0 = 200, y0 = 150, width = 160, height = 80;
  for (const auto& [new_width, new_height] : {std::pair{320, 160}, std::pair{80, 40}, std::pair{200, 100}}) {
    const Camera resampled = camera.Resampled(x0, y0, width, height, new_width, new_height);
    const double sx = static_cast<double>(new_width) / width, sy = static_cast<double>(new_height) / height;
    const Eigen::Vector3d point(31.0, -12.5, 420.0);
    const Eigen::Vector2d expected = Camera::ToResampled(camera.Project(point), x0, y0, sx, sy);
    EXPECT_LT((resampled.Project(point) - expected).norm(), 1e-9);

    cv::Mat ramp(480, 640, CV_32FC2);
    for (int y = 0; y < ramp.rows; ++y) {
      for (int x = 0; x < ramp.cols; ++x) ramp.at<cv::Vec2f>(y, x) = cv::Vec2f(static_cast<float>(x), static_cast<float>(y));
    }
    cv::Mat resized;
    cv::resize(ramp(cv::Rect(x0, y0, width, height)), resized, cv::Size(new_width, new_height), 0, 0,
               sx < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
    // Interior pixels only: at the border cv::resize replicates the edge.
    for (int y = 4; y < new_height - 4; y += 7) {
      for (int x = 4; x < new_width - 4; x += 7) {
        const cv::Vec2f source = resized.at<cv::Vec2f>(y, x);
        const Eigen::Vector2d back = Camera::ToResampled(Eigen::Vector2d(source[0], source[1]), x0, y0, sx, sy);
        EXPECT_NEAR(back.x(), x, 1e-3) << new_width << "x" << new_height;
        EXPECT_NEAR(back.y(), y, 1e-3) << new_width << "x" << new_height;
      }
    }
  }
}

TEST(CameraTest, ScalingAndCroppingMoveThePrincipalPointWithThePixels) {
  const Camera camera = Camera::Default(640, 480);
  const Eigen::Vector3d point(-40.0, 22.0, 380.0);
  const Eigen::Vector2d pixel = camera.Project(point);
  const Camera half = camera.Scaled(0.5);
  EXPECT_EQ(half.width, 320);
  EXPECT_LT((half.Project(point) - ((pixel.array() + 0.5) * 0.5 - 0.5).matrix()).norm(), 1e-9);
  const Camera cropped = camera.Cropped(100, 50, 200, 200);
  EXPECT_LT((cropped.Project(point) - (pixel - Eigen::Vector2d(100, 50))).norm(), 1e-9);
  // A pixel's ray projects back onto that pixel.
  EXPECT_LT((camera.Project(500 * camera.Ray(pixel)) - pixel).norm(), 1e-9);
}

}  // namespace
}  // namespace gazedirector
