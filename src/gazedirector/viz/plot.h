#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace gazedirector {

// A small line chart drawn with OpenCV: series with optional shaded bands
// (for interquartile ranges), axes with round ticks, labels and a legend.
class LinePlot {
 public:
  struct Series {
    std::string name;
    std::vector<double> x, y, low, high;
    cv::Scalar colour;
  };

  LinePlot(std::string title, std::string x_label, std::string y_label)
      : title_(std::move(title)), x_label_(std::move(x_label)), y_label_(std::move(y_label)) {}

  // `low` and `high`, when given, shade a band around the line.
  void AddSeries(std::string name, std::vector<double> x, std::vector<double> y, cv::Scalar colour,
                 std::vector<double> low = {}, std::vector<double> high = {});
  void SetYRange(double low, double high) { y_min_ = low, y_max_ = high, fixed_y_ = true; }
  void SetXRange(double low, double high) { x_min_ = low, x_max_ = high, fixed_x_ = true; }

  cv::Mat Draw(int width = 640, int height = 420) const;

 private:
  std::string title_, x_label_, y_label_;
  std::vector<Series> series_;
  double x_min_ = 0, x_max_ = 1, y_min_ = 0, y_max_ = 1;
  bool fixed_x_ = false, fixed_y_ = false;
};

// Per position i, the median and quartiles over the sequences that reach it;
// shorter sequences hold their last value (a converged fit stays put).
struct QuantileCurves {
  std::vector<double> median, q25, q75;
};
QuantileCurves QuantilesByIndex(const std::vector<std::vector<double>>& sequences, int length);

// Two or more pictures side by side on a white canvas.
cv::Mat SideBySide(const std::vector<cv::Mat>& pictures, int gap = 10);

}  // namespace gazedirector
