#include "gazedirector/viz/plot.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace gazedirector {
namespace {

// LinePlot's frame at its default size: the plotting area's corners.
constexpr int kWidth = 640, kHeight = 420;
const cv::Rect kArea(70, 40, kWidth - 70 - 20, kHeight - 40 - 55);
const cv::Scalar kRed(0, 0, 255);
// Where a line drawn along the area's edge may reach: half its thickness of 2
// and its antialiasing.
const cv::Rect kAreaAndEdge(kArea.x - 3, kArea.y - 3, kArea.width + 6, kArea.height + 6);

bool IsReddish(const cv::Vec3b& bgr) { return bgr[2] > 150 && bgr[1] < 110 && bgr[0] < 110; }

int CountReddish(const cv::Mat& canvas, const cv::Rect& region) {
  int count = 0;
  for (int y = region.y; y < region.y + region.height; ++y) {
    for (int x = region.x; x < region.x + region.width; ++x) count += IsReddish(canvas.at<cv::Vec3b>(y, x));
  }
  return count;
}

// The plotting area's pixel of (x, y) for ranges [0, x1] and [0, y1].
cv::Point PixelOf(double x, double y, double x1, double y1) {
  return {static_cast<int>(std::lround(kArea.x + x / x1 * kArea.width)),
          static_cast<int>(std::lround(kArea.y + kArea.height - y / y1 * kArea.height))};
}

// The canvas without the legend (top right of the area), whose sample line
// has the series' colour.
cv::Mat WithoutLegend(const cv::Mat& canvas) {
  cv::Mat masked = canvas.clone();
  masked(cv::Rect(kArea.x + kArea.width - 160, kArea.y, 160, 40)).setTo(cv::Scalar(255, 255, 255));
  return masked;
}

TEST(QuantilesByIndexTest, ShorterSequencesHoldTheirLastValue) {
  const std::vector<std::vector<double>> sequences = {{10, 8, 6, 4}, {20, 10}, {5, 5, 5}, {}, {1, 2, 3, 4, 5}};
  const QuantileCurves curves = QuantilesByIndex(sequences, 5);
  ASSERT_EQ(curves.median.size(), 5u);
  // Index 0 over {10, 20, 5, 1}; index 4 over {4 (held), 10 (held), 5 (held), 5}.
  EXPECT_DOUBLE_EQ(curves.median[0], 7.5);
  EXPECT_DOUBLE_EQ(curves.q25[0], 4.0);
  EXPECT_DOUBLE_EQ(curves.q75[0], 12.5);
  EXPECT_DOUBLE_EQ(curves.median[4], 5.0);
  EXPECT_DOUBLE_EQ(curves.q25[4], 4.75);
  EXPECT_DOUBLE_EQ(curves.q75[4], 6.25);
  for (int i = 0; i < 5; ++i) {
    EXPECT_LE(curves.q25[i], curves.median[i]);
    EXPECT_LE(curves.median[i], curves.q75[i]);
  }
}

TEST(LinePlotTest, DrawsASeriesThroughItsPointsInsideTheAxes) {
  LinePlot plot("title", "x", "y");
  plot.AddSeries("rising", {0, 5, 10}, {0, 5, 10}, kRed);
  plot.SetXRange(0, 10);
  plot.SetYRange(0, 10);
  const cv::Mat canvas = plot.Draw(kWidth, kHeight);
  ASSERT_EQ(canvas.size(), cv::Size(kWidth, kHeight));
  for (double v : {2.0, 5.0, 7.0}) {
    const cv::Point on_line = PixelOf(v, v, 10, 10);
    EXPECT_TRUE(IsReddish(canvas.at<cv::Vec3b>(on_line))) << "at " << v;
    EXPECT_FALSE(IsReddish(canvas.at<cv::Vec3b>(PixelOf(v, v + 2, 10, 10)))) << "above " << v;
  }
  // Nothing red outside the area.
  cv::Mat outside = canvas.clone();
  outside(kAreaAndEdge).setTo(cv::Scalar(255, 255, 255));
  EXPECT_EQ(CountReddish(outside, cv::Rect(0, 0, kWidth, kHeight)), 0);
}

TEST(LinePlotTest, ShadesABandAroundTheLine) {
  LinePlot plot("title", "x", "y");
  plot.AddSeries("median", {0, 10}, {5, 5}, kRed, {3, 3}, {7, 7});
  plot.SetXRange(0, 10);
  plot.SetYRange(0, 10);
  const cv::Mat canvas = plot.Draw(kWidth, kHeight);
  // Between the grid lines (every 2).
  const cv::Vec3b in_band = canvas.at<cv::Vec3b>(PixelOf(5, 6.5, 10, 10));
  const cv::Vec3b outside_band = canvas.at<cv::Vec3b>(PixelOf(5, 8.5, 10, 10));
  EXPECT_GT(in_band[2], 200);  // a light red tint: a quarter of the colour
  EXPECT_LT(in_band[1], 215);
  EXPECT_GT(in_band[1], 150);
  EXPECT_EQ(outside_band, cv::Vec3b(255, 255, 255));
}

TEST(LinePlotTest, ItsAutomaticRangeHoldsNegativeFlatAndSinglePointSeries) {
  const std::vector<std::pair<std::vector<double>, std::vector<double>>> cases = {
      {{0, 1, 2, 3}, {-9, -7, -6, -5}},  // all below zero
      {{0, 1, 2, 3}, {4, 4, 4, 4}},      // flat
      {{2, 2}, {3, 8}},                   // one x
  };
  for (const auto& [x, y] : cases) {
    LinePlot plot("title", "x", "y");
    plot.AddSeries("s", x, y, kRed);
    const cv::Mat canvas = WithoutLegend(plot.Draw(kWidth, kHeight));
    cv::Mat outside = canvas.clone();
    outside(kAreaAndEdge).setTo(cv::Scalar(255, 255, 255));
    EXPECT_GT(CountReddish(canvas, kArea), 100) << "first value " << y.front();
    EXPECT_EQ(CountReddish(outside, cv::Rect(0, 0, kWidth, kHeight)), 0) << "first value " << y.front();
  }
}

TEST(LinePlotTest, LeavesAGapWhereAValueIsMissing) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  LinePlot plot("title", "x", "y");
  plot.AddSeries("with a gap", {0, 1, 2, 3, 4}, {1, 2, nan, 4, 5}, kRed, {0.5, 1.5, nan, 3.5, 4.5},
                 {1.5, 2.5, nan, 4.5, 5.5});
  plot.SetXRange(0, 4);
  plot.SetYRange(0, 6);
  const cv::Mat canvas = plot.Draw(kWidth, kHeight);
  EXPECT_TRUE(IsReddish(canvas.at<cv::Vec3b>(PixelOf(0.5, 1.5, 4, 6))));
  EXPECT_TRUE(IsReddish(canvas.at<cv::Vec3b>(PixelOf(3.5, 4.5, 4, 6))));
  // Nothing between the two runs, and no line toward a missing point.
  const cv::Point gap_start = PixelOf(1.2, 6, 4, 6), gap_end = PixelOf(2.8, 0, 4, 6);
  EXPECT_EQ(CountReddish(canvas, cv::Rect(gap_start, gap_end)), 0);
  const cv::Point above_start = PixelOf(0, 6, 4, 6), above_end = PixelOf(1.2, 3, 4, 6);
  EXPECT_EQ(CountReddish(canvas, cv::Rect(above_start, above_end)), 0);
  EXPECT_EQ(canvas.at<cv::Vec3b>(PixelOf(2, 3, 4, 6)), cv::Vec3b(255, 255, 255));
  EXPECT_GT(CountReddish(WithoutLegend(canvas), kArea), 100);
}

TEST(SideBySideTest, PlacesPicturesLeftToRightOnWhite) {
  const cv::Mat a(30, 20, CV_8UC3, cv::Scalar(0, 0, 255)), b(50, 40, CV_8UC3, cv::Scalar(255, 0, 0));
  const cv::Mat canvas = SideBySide({a, b}, 10);
  EXPECT_EQ(canvas.size(), cv::Size(10 + 20 + 10 + 40 + 10, 50));
  EXPECT_EQ(canvas.at<cv::Vec3b>(0, 10), cv::Vec3b(0, 0, 255));
  EXPECT_EQ(canvas.at<cv::Vec3b>(29, 29), cv::Vec3b(0, 0, 255));
  EXPECT_EQ(canvas.at<cv::Vec3b>(40, 20), cv::Vec3b(255, 255, 255));  // below the shorter one
  EXPECT_EQ(canvas.at<cv::Vec3b>(49, 40), cv::Vec3b(255, 0, 0));
  EXPECT_EQ(canvas.at<cv::Vec3b>(10, 35), cv::Vec3b(255, 255, 255));  // the gap
}

}  // namespace
}  // namespace gazedirector
