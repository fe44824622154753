#include "gazedirector/viz/draw_face.h"

#include <algorithm>
#include <array>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "gazedirector/geometry/rotation.h"

namespace gazedirector {
namespace {

cv::Point2f ToPoint(const Eigen::Vector2d& p) { return {static_cast<float>(p.x()), static_cast<float>(p.y())}; }

struct Contour {
  int first, last;
  bool closed;
};
constexpr std::array<Contour, 9> kContours = {{{0, 16, false}, {17, 21, false}, {22, 26, false}, {27, 30, false},
                                               {31, 35, false}, {36, 41, true}, {42, 47, true}, {48, 59, true},
                                               {60, 67, true}}};

}  // namespace

int LineThickness(const cv::Mat& image) { return std::max(1, std::min(image.cols, image.rows) / 400); }

void DrawFace(cv::Mat& image, const Face& face, const Camera& camera) {
  // Sizes follow the face, so that small faces in group photos stay readable.
  const double size = std::max(face.box.width, 20.0);
  const int thickness = std::max(1, static_cast<int>(size / 200));
  const cv::Scalar green(80, 220, 80), white(255, 255, 255);
  const cv::RotatedRect box({static_cast<float>(face.box.x + 0.5 * face.box.width), static_cast<float>(face.box.y + 0.5 * face.box.height)},
                            {static_cast<float>(face.box.width), static_cast<float>(face.box.height)},
                            static_cast<float>(RadToDeg(face.box_roll)));
  std::array<cv::Point2f, 4> corners;
  box.points(corners.data());
  std::vector<cv::Point> outline;
  for (const cv::Point2f& corner : corners) outline.push_back(corner * 16);
  cv::polylines(image, outline, true, cv::Scalar(255, 180, 0), thickness, cv::LINE_AA, 4);
  for (const Contour& c : kContours) {
    std::vector<cv::Point> points;
    for (int i = c.first; i <= c.last; ++i) points.push_back(ToPoint(face.landmarks[i]) * 16);
    cv::polylines(image, points, c.closed, green, thickness, cv::LINE_AA, 4);
  }
  const int radius = std::max(16, static_cast<int>(16 * size / 120));
  for (const auto& p : face.landmarks) cv::circle(image, ToPoint(p) * 16, radius, white, -1, cv::LINE_AA, 4);

  // Head axes, 40 mm long, drawn from the nose tip.
  const Eigen::Vector3d kNoseTip(0.0, -4.1, -130.7);  // in the head frame (the mean face's point 30)
  const Eigen::Vector3d origin = face.pose.rotation * kNoseTip + face.pose.translation;
  if (origin.z() > 1) {
    const std::array<cv::Scalar, 3> colours = {cv::Scalar(0, 0, 255), cv::Scalar(0, 200, 0), cv::Scalar(255, 0, 0)};
    for (int axis = 0; axis < 3; ++axis) {
      // x and y as they are; z drawn toward the viewer (the way the face looks).
      const double sign = axis == 2 ? -1.0 : 1.0;
      const Eigen::Vector3d tip = origin + face.pose.rotation.col(axis) * 40.0 * sign;  // mm
      if (tip.z() <= 1) continue;
      cv::arrowedLine(image, ToPoint(camera.Project(origin)), ToPoint(camera.Project(tip)), colours[axis], thickness + 1,
                      cv::LINE_AA, 0, 0.15);
    }
  }
  const std::string label = fmt::format("face {}  {:.2f}", face.id, face.confidence);
  const double font = std::clamp(size / 400, 0.3, 2.0);
  const cv::Rect bounds = box.boundingRect();
  cv::putText(image, label, cv::Point(bounds.x, static_cast<int>(bounds.y - 4 - size / 100)),
              cv::FONT_HERSHEY_SIMPLEX, font, white, thickness, cv::LINE_AA);
}

}  // namespace gazedirector
