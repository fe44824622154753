#include "gazedirector/redirect/eye_image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "gazedirector/util/statistics.h"

namespace gazedirector {

cv::Vec3f Bilinear(const cv::Mat& image, float x, float y) {
  x = std::clamp(x, 0.0f, image.cols - 1.001f), y = std::clamp(y, 0.0f, image.rows - 1.001f);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float fx = x - x0, fy = y - y0;
  const int x1 = std::min(x0 + 1, image.cols - 1), y1 = std::min(y0 + 1, image.rows - 1);
  return (1 - fy) * ((1 - fx) * image.at<cv::Vec3f>(y0, x0) + fx * image.at<cv::Vec3f>(y0, x1)) +
         fy * ((1 - fx) * image.at<cv::Vec3f>(y1, x0) + fx * image.at<cv::Vec3f>(y1, x1));
}

cv::Mat BlurredWithin(const cv::Mat& image, const cv::Rect& area, double sigma) {
  const cv::Rect around = GrownWithin(area, static_cast<int>(std::ceil(3 * sigma)), image.size());
  cv::Mat blurred = cv::Mat::zeros(image.size(), image.type());
  cv::Mat part = blurred(around);
  cv::GaussianBlur(image(around), part, cv::Size(0, 0), sigma);
  return blurred;
}

void BlurSeam(cv::Mat& image, const cv::Mat& mask, const cv::Rect& area, double sigma) {
  const cv::Rect around = GrownWithin(area, static_cast<int>(std::ceil(3 * sigma)), image.size());
  cv::Mat inside;
  mask.convertTo(inside, CV_32F, 1.0 / 255);
  const cv::Mat share = BlurredWithin(inside, around, sigma);
  const cv::Mat blurred = BlurredWithin(image, around, sigma);
  for (int y = around.y; y < around.y + around.height; ++y) {
    for (int x = around.x; x < around.x + around.width; ++x) {
      const float s = share.at<float>(y, x), band = 4 * s * (1 - s);
      if (band > 0) image.at<cv::Vec3f>(y, x) = band * blurred.at<cv::Vec3f>(y, x) + (1 - band) * image.at<cv::Vec3f>(y, x);
    }
  }
}

cv::Mat MixedAcrossEdge(const cv::Mat& image, const cv::Mat& mask, const cv::Mat& edge_distance) {
  cv::Mat out = image.clone();
  const cv::Rect inside(0, 0, image.cols, image.rows);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const float d = edge_distance.at<float>(y, x);
      if (!mask.at<uchar>(y, x) || std::abs(d) >= 0.5f) continue;
      // Within half a pixel of a straight edge, the neighbour along its
      // normal's larger component lies across it.
      cv::Vec3f across(0, 0, 0);
      int count = 0;
      for (const cv::Point step : {cv::Point(1, 0), cv::Point(-1, 0), cv::Point(0, 1), cv::Point(0, -1)}) {
        const cv::Point n(x + step.x, y + step.y);
        if (!inside.contains(n) || !mask.at<uchar>(n) || (edge_distance.at<float>(n) > 0) == (d > 0)) continue;
        across += image.at<cv::Vec3f>(n);
        ++count;
      }
      if (count == 0) continue;
      const float own = 0.5f + std::abs(d);
      out.at<cv::Vec3f>(y, x) = own * image.at<cv::Vec3f>(y, x) + (1 - own) / count * across;
    }
  }
  return out;
}

cv::Mat NearbyColour(const cv::Mat& image, const cv::Mat& shown, const cv::Rect& area, double sigma,
                     const cv::Mat& typical) {
  constexpr float kTypicalWeight = 0.01f;  // against a blurred density of up to 1
  cv::Mat sum(image.size(), CV_32FC3, cv::Scalar::all(0)), density;
  image.copyTo(sum, shown);
  shown.convertTo(density, CV_32F, 1.0 / 255);
  sum = BlurredWithin(sum, area, sigma);
  density = BlurredWithin(density, area, sigma);
  cv::Mat nearby = typical.clone();
  for (int y = area.y; y < area.y + area.height; ++y) {
    for (int x = area.x; x < area.x + area.width; ++x) {
      const cv::Vec3f& usual = typical.at<cv::Vec3f>(y, x);
      nearby.at<cv::Vec3f>(y, x) =
          (sum.at<cv::Vec3f>(y, x) + kTypicalWeight * usual) / (density.at<float>(y, x) + kTypicalWeight);
    }
  }
  return nearby;
}

cv::Mat NearbyColour(const cv::Mat& image, const cv::Mat& shown, const cv::Rect& area, double sigma,
                     const cv::Vec3f& typical) {
  return NearbyColour(image, shown, area, sigma, cv::Mat(shown.size(), CV_32FC3, cv::Scalar(typical)));
}

cv::Mat DepthInside(const cv::Mat& mask) {
  cv::Mat depth(mask.size(), CV_32F, cv::Scalar(0));
  const cv::Rect inside = cv::boundingRect(mask);
  if (inside.empty()) return depth;
  // The ring of outside pixels around the mask holds the nearest outside
  // pixel of every inside one (a farther one, clamped onto the ring, is
  // nearer); where the mask meets the image's edge there is none, as in the
  // whole image.
  const cv::Rect around = GrownWithin(inside, 1, mask.size());
  cv::distanceTransform(mask(around), depth(around), cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return depth;
}

double MedianUnder(const cv::Mat& values, const cv::Mat& mask, double none) {
  std::vector<double> under;
  for (int y = 0; y < values.rows; ++y) {
    for (int x = 0; x < values.cols; ++x) {
      if (mask.at<uchar>(y, x)) under.push_back(values.at<float>(y, x));
    }
  }
  return under.empty() ? none : Median(std::move(under));
}

cv::Vec3f MedianColour(const cv::Mat& image, const cv::Mat& mask) {
  std::array<cv::Mat, 3> channels;
  cv::split(image, channels.data());
  cv::Vec3f colour;
  for (int c = 0; c < 3; ++c) colour[c] = static_cast<float>(MedianUnder(channels[c], mask, 0));
  return colour;
}

}  // namespace gazedirector
