#include "gazedirector/fit/iris_alignment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "gazedirector/model/eye_region_topology.h"
#include "gazedirector/render/model_bounds.h"

namespace gazedirector {
namespace {

constexpr double kDarkShare = 0.3;

struct ProjectedIris {
  Eigen::Vector2d centre;
  double radius = 0;
};

// The limbus ring of `eye`'s posed eyeball, projected into `camera`.
ProjectedIris ProjectIris(const PosedModel& posed, const Camera& camera, int eye) {
  const Eigen::Matrix3Xf& positions = posed.parts[EyeballPart(eye)].positions;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int v : topology::kLimbus) centre += positions.col(v).cast<double>();
  centre /= static_cast<double>(topology::kLimbus.size());
  ProjectedIris iris{camera.Project(centre), 0.0};
  for (int v : topology::kLimbus) {
    iris.radius = std::max(iris.radius, (camera.Project(positions.col(v).cast<double>()) - iris.centre).norm());
  }
  return iris;
}

}  // namespace

std::array<double, 2> IrisMisalignment(const cv::Mat& image, const Camera& camera, const Parameters& phi,
                                       std::array<bool, 2> eyes, Renderer& renderer) {
  std::array<double, 2> misalignment = {std::numeric_limits<double>::quiet_NaN(),
                                        std::numeric_limits<double>::quiet_NaN()};
  if (!eyes[0] && !eyes[1]) return misalignment;
  renderer.set_eyes(eyes[0], eyes[1]);
  renderer.Pose(phi);
  const cv::Rect region = ModelBounds(renderer.posed(), camera, 0.02, eyes) & cv::Rect(0, 0, image.cols, image.rows);
  if (region.empty()) return misalignment;
  const Camera crop = camera.Cropped(region.x, region.y, region.width, region.height);
  RenderBuffers buffers;
  renderer.Rasterize(crop, buffers);
  cv::Mat grey;
  cv::cvtColor(image(region), grey, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);

  for (int eye = 0; eye < 2; ++eye) {
    if (!eyes[eye]) continue;
    struct Pixel {
      int x, y;
      uchar luminance;
    };
    std::vector<Pixel> pixels;
    for (int pixel : buffers.foreground) {
      if (buffers.PartAt(pixel) != EyeballPart(eye)) continue;
      const int x = pixel % region.width, y = pixel / region.width;
      pixels.push_back({x, y, grey.at<uchar>(y, x)});
    }
    if (static_cast<int>(pixels.size()) < kMinEyeballPixels) continue;
    const std::size_t dark = std::max<std::size_t>(1, static_cast<std::size_t>(kDarkShare * pixels.size()));
    std::nth_element(pixels.begin(), pixels.begin() + (dark - 1), pixels.end(),
                     [](const Pixel& a, const Pixel& b) { return a.luminance < b.luminance; });
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < dark; ++i) centroid += Eigen::Vector2d(pixels[i].x, pixels[i].y);
    centroid /= static_cast<double>(dark);
    const ProjectedIris iris = ProjectIris(renderer.posed(), crop, eye);
    if (iris.radius > 0) misalignment[eye] = (centroid - iris.centre).norm() / iris.radius;
  }
  return misalignment;
}

double WorstIrisMisalignment(const cv::Mat& image, const Camera& camera, const Parameters& phi,
                             std::array<bool, 2> eyes, Renderer& renderer) {
  double worst = 0;
  for (double offset : IrisMisalignment(image, camera, phi, eyes, renderer)) {
    if (std::isfinite(offset)) worst = std::max(worst, offset);
  }
  return worst;
}

}  // namespace gazedirector
