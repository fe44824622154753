#include "gazedirector/viz/plot.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "gazedirector/util/statistics.h"

namespace gazedirector {
namespace {

double RoundStep(double span, int ticks) {
  const double raw = span / std::max(ticks, 1);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (factor * magnitude >= raw) return factor * magnitude;
  }
  return 10 * magnitude;
}

std::string TickLabel(double value, double step) {
  const int decimals = step >= 1 ? 0 : static_cast<int>(std::ceil(-std::log10(step)));
  return fmt::format("{:.{}f}", value, decimals);
}

// The stretches of two or more consecutive indices at which every one of
// `columns` is finite: a missing value breaks a line and its band.
std::vector<std::vector<std::size_t>> FiniteRuns(std::initializer_list<const std::vector<double>*> columns) {
  std::size_t length = std::numeric_limits<std::size_t>::max();
  for (const auto* column : columns) length = std::min(length, column->size());
  std::vector<std::vector<std::size_t>> runs(1);
  for (std::size_t i = 0; i < length; ++i) {
    if (std::all_of(columns.begin(), columns.end(), [i](const auto* column) { return std::isfinite((*column)[i]); })) {
      runs.back().push_back(i);
    } else if (!runs.back().empty()) {
      runs.emplace_back();
    }
  }
  std::erase_if(runs, [](const std::vector<std::size_t>& run) { return run.size() < 2; });
  return runs;
}

// The plotting area and the data ranges it shows.
struct PlotFrame {
  cv::Rect area;
  double x0, x1, y0, y1;

  cv::Point2d ToPixel(double x, double y) const {
    return {area.x + (x - x0) / (x1 - x0) * area.width, area.y + area.height - (y - y0) / (y1 - y0) * area.height};
  }
};

const cv::Scalar kGrey(200, 200, 200), kInk(40, 40, 40);

// Ranges that hold every finite value (y from 0 or below), where not fixed.
void FitRanges(const std::vector<LinePlot::Series>& series, bool fixed_x, bool fixed_y, PlotFrame& frame) {
  if (fixed_x && fixed_y) return;
  double xa = std::numeric_limits<double>::max(), xb = -xa, ya = xa, yb = -xa;
  for (const LinePlot::Series& s : series) {
    for (double v : s.x) {
      if (std::isfinite(v)) xa = std::min(xa, v), xb = std::max(xb, v);
    }
    for (const auto* values : {&s.y, &s.low, &s.high}) {
      for (double v : *values) {
        if (std::isfinite(v)) ya = std::min(ya, v), yb = std::max(yb, v);
      }
    }
  }
  // A single x or a flat series gets a range of its own around its value.
  if (!fixed_x && xb > xa) frame.x0 = xa, frame.x1 = xb;
  if (!fixed_x && xb == xa) frame.x0 = xa - 0.5, frame.x1 = xa + 0.5;
  if (!fixed_y && yb >= ya) {
    frame.y0 = std::min(0.0, ya);
    frame.y1 = yb > frame.y0 ? yb + 0.05 * (yb - frame.y0) : frame.y0 + 1;
  }
}

// Horizontal grid lines with their values, x ticks below, and the frame.
void DrawGrid(cv::Mat& canvas, const PlotFrame& frame) {
  const double y_step = RoundStep(frame.y1 - frame.y0, 5), x_step = RoundStep(frame.x1 - frame.x0, 8);
  for (double y = std::ceil(frame.y0 / y_step) * y_step; y <= frame.y1 + 1e-9; y += y_step) {
    const cv::Point2d p = frame.ToPixel(frame.x0, y);
    cv::line(canvas, p, frame.ToPixel(frame.x1, y), kGrey, 1);
    // Right-aligned beside the axis, clear of the rotated axis label.
    const std::string label = TickLabel(y, y_step);
    const int label_width = cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, 0.4, 1, nullptr).width;
    cv::putText(canvas, label, p + cv::Point2d(-6 - label_width, 4), cv::FONT_HERSHEY_SIMPLEX, 0.4, kInk, 1, cv::LINE_AA);
  }
  for (double x = std::ceil(frame.x0 / x_step) * x_step; x <= frame.x1 + 1e-9; x += x_step) {
    const cv::Point2d p = frame.ToPixel(x, frame.y0);
    cv::line(canvas, p, p + cv::Point2d(0, 4), kInk, 1);
    cv::putText(canvas, TickLabel(x, x_step), p + cv::Point2d(-8, 18), cv::FONT_HERSHEY_SIMPLEX, 0.4, kInk, 1, cv::LINE_AA);
  }
  cv::rectangle(canvas, frame.area, kInk, 1);
}

// The series' band, shaded at a quarter of its colour, and its line.
void DrawSeries(cv::Mat& canvas, const PlotFrame& frame, const LinePlot::Series& s) {
  if (!s.low.empty() && s.low.size() == s.x.size() && s.high.size() == s.x.size()) {
    std::vector<std::vector<cv::Point>> bands;
    for (const auto& run : FiniteRuns({&s.x, &s.low, &s.high})) {
      std::vector<cv::Point>& band = bands.emplace_back();
      for (std::size_t i : run) band.push_back(frame.ToPixel(s.x[i], s.high[i]));
      for (auto i = run.rbegin(); i != run.rend(); ++i) band.push_back(frame.ToPixel(s.x[*i], s.low[*i]));
    }
    cv::Mat layer = canvas.clone();
    cv::fillPoly(layer, bands, s.colour, cv::LINE_AA);
    cv::addWeighted(layer, 0.25, canvas, 0.75, 0, canvas);
  }
  for (const auto& run : FiniteRuns({&s.x, &s.y})) {
    for (std::size_t k = 1; k < run.size(); ++k) {
      cv::line(canvas, frame.ToPixel(s.x[run[k - 1]], s.y[run[k - 1]]), frame.ToPixel(s.x[run[k]], s.y[run[k]]),
               s.colour, 2, cv::LINE_AA);
    }
  }
}

// The legend in the top right corner, as wide as its longest name, on white.
void DrawLegend(cv::Mat& canvas, const cv::Rect& area, const std::vector<LinePlot::Series>& series) {
  if (series.empty()) return;
  int name_width = 0;
  for (const LinePlot::Series& s : series) {
    name_width = std::max(name_width, cv::getTextSize(s.name, cv::FONT_HERSHEY_SIMPLEX, 0.42, 1, nullptr).width);
  }
  const int legend_x = area.x + area.width - name_width - 38;
  const cv::Rect box(legend_x - 6, area.y + 4, name_width + 40, 18 * static_cast<int>(series.size()) + 6);
  cv::rectangle(canvas, box, cv::Scalar(255, 255, 255), cv::FILLED);
  cv::rectangle(canvas, box, kGrey, 1);
  int legend_y = area.y + 18;
  for (const LinePlot::Series& s : series) {
    cv::line(canvas, {legend_x, legend_y - 4}, {legend_x + 20, legend_y - 4}, s.colour, 2);
    cv::putText(canvas, s.name, {legend_x + 26, legend_y}, cv::FONT_HERSHEY_SIMPLEX, 0.42, kInk, 1, cv::LINE_AA);
    legend_y += 18;
  }
}

}  // namespace

void LinePlot::AddSeries(std::string name, std::vector<double> x, std::vector<double> y, cv::Scalar colour,
                         std::vector<double> low, std::vector<double> high) {
  series_.push_back({std::move(name), std::move(x), std::move(y), std::move(low), std::move(high), colour});
}

cv::Mat LinePlot::Draw(int width, int height) const {
  cv::Mat canvas(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 70, right = 20, top = 40, bottom = 55;
  PlotFrame frame{cv::Rect(left, top, width - left - right, height - top - bottom), x_min_, x_max_, y_min_, y_max_};
  FitRanges(series_, fixed_x_, fixed_y_, frame);
  DrawGrid(canvas, frame);
  for (const Series& s : series_) DrawSeries(canvas, frame, s);
  DrawLegend(canvas, frame.area, series_);
  const cv::Rect& area = frame.area;
  cv::putText(canvas, title_, {left, 25}, cv::FONT_HERSHEY_SIMPLEX, 0.55, kInk, 1, cv::LINE_AA);
  cv::putText(canvas, x_label_, {area.x + area.width / 2 - 60, height - 12}, cv::FONT_HERSHEY_SIMPLEX, 0.45, kInk, 1, cv::LINE_AA);
  cv::Mat rotated(30, area.height, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(rotated, y_label_, {area.height / 2 - static_cast<int>(3.5 * y_label_.size()), 20}, cv::FONT_HERSHEY_SIMPLEX, 0.45, kInk, 1, cv::LINE_AA);
  cv::rotate(rotated, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
  rotated.copyTo(canvas(cv::Rect(2, area.y, rotated.cols, rotated.rows)));
  return canvas;
}

QuantileCurves QuantilesByIndex(const std::vector<std::vector<double>>& sequences, int length) {
  QuantileCurves curves;
  for (int i = 0; i < length; ++i) {
    std::vector<double> values;
    for (const auto& sequence : sequences) {
      if (!sequence.empty()) values.push_back(sequence[std::min<std::size_t>(i, sequence.size() - 1)]);
    }
    curves.median.push_back(Median(values));
    curves.q25.push_back(Quantile(values, 0.25));
    curves.q75.push_back(Quantile(values, 0.75));
  }
  return curves;
}

cv::Mat SideBySide(const std::vector<cv::Mat>& pictures, int gap) {
  int width = gap, height = 0;
  for (const cv::Mat& p : pictures) width += p.cols + gap, height = std::max(height, p.rows);
  cv::Mat canvas(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  int x = gap;
  for (const cv::Mat& p : pictures) {
    p.copyTo(canvas(cv::Rect(x, 0, p.cols, p.rows)));
    x += p.cols + gap;
  }
  return canvas;
}

}  // namespace gazedirector
