#include "gazedirector/viz/draw_fit.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::FitStill;
using testing::FittedStill;
using testing::SharedModel;

// The overlay's iris outline colour (light blue), antialiased edges included.
cv::Mat IrisOutlinePixels(const cv::Mat& overlay) {
  cv::Mat mask;
  cv::inRange(overlay, cv::Scalar(215, 160, 0), cv::Scalar(255, 240, 110), mask);
  return mask;
}

// Each fitted iris is outlined around where the fit put it, and nothing else
// is drawn in that colour; turning the eyes moves the outlines with them.
TEST(DrawFitTest, OutlinesEachFittedIrisWhereTheFitPutsIt) {
  const FittedStill& still = FitStill("images/d30.jpg");
  ASSERT_TRUE(still.fit.good) << still.fit.note;
  Renderer renderer(SharedModel());
  auto outlines = [&](const Parameters& phi, std::array<cv::Point2d, 2>& centres) {
    cv::Mat overlay = still.image.clone();
    DrawFit(overlay, still.camera, phi, true, {true, true}, renderer);
    const std::array<EyeGaze, 2> gazes = EyeGazes(phi);
    for (int eye = 0; eye < 2; ++eye) {
      const Eigen::Vector2d c = still.camera.Project(gazes[eye].centre + 12.0 * gazes[eye].gaze);
      centres[eye] = {c.x(), c.y()};
    }
    return IrisOutlinePixels(overlay);
  };
  std::array<cv::Point2d, 2> centres;
  const cv::Mat fitted = outlines(still.fit.phi, centres);
  // An iris is about 6 mm across in radius terms; the outline lies within 8 mm of its centre.
  const double reach_px = still.camera.fx * 8.0 / still.fit.phi.translation().z();
  std::array<int, 2> near = {0, 0};
  int elsewhere = 0;
  for (int y = 0; y < fitted.rows; ++y) {
    for (int x = 0; x < fitted.cols; ++x) {
      if (!fitted.at<uchar>(y, x)) continue;
      bool counted = false;
      for (int eye = 0; eye < 2; ++eye) {
        if (cv::norm(cv::Point2d(x, y) - centres[eye]) < reach_px) ++near[eye], counted = true;
      }
      elsewhere += !counted;
    }
  }
  // A visible iris outline runs for at least twice the reach (a circle of radius 6 mm, 4.7 times).
  for (int eye = 0; eye < 2; ++eye) EXPECT_GT(near[eye], 2 * reach_px) << "eye " << eye;
  EXPECT_LT(elsewhere, 0.05 * (near[0] + near[1]));

  Parameters turned = still.fit.phi;
  turned.gaze_yaw() += 30;
  std::array<cv::Point2d, 2> turned_centres;
  const cv::Mat moved = outlines(turned, turned_centres);
  cv::Mat both;
  cv::bitwise_and(fitted, moved, both);
  EXPECT_LT(cv::countNonZero(both), 0.3 * cv::countNonZero(fitted));
}

}  // namespace
}  // namespace gazedirector
