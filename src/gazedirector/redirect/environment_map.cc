#include "gazedirector/redirect/environment_map.h"

#include <algorithm>
#include <cmath>

namespace gazedirector {
namespace {

float Smoothstep(float edge0, float edge1, float x) {
  const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}

AreaLight Light(Eigen::Vector3d toward, double radius, double feather, double intensity,
                Eigen::Vector3d tint = Eigen::Vector3d::Ones(), double inner = 0) {
  return {toward.normalized(), radius, feather, intensity * tint, inner};
}

}  // namespace

Eigen::Vector3f EnvironmentMap::Radiance(const Eigen::Vector3f& direction) const {
  Eigen::Vector3f out = surround.cast<float>();
  for (const AreaLight& light : lights) {
    const float cosine = std::clamp(direction.dot(light.direction.cast<float>()), -1.0f, 1.0f);
    const float angle = std::acos(cosine);
    const float r = static_cast<float>(light.radius_rad), f = static_cast<float>(light.feather_rad);
    float weight = 1.0f - Smoothstep(r, r + f, angle);
    if (light.inner_radius_rad > 0) weight *= Smoothstep(static_cast<float>(light.inner_radius_rad) - f,
                                                         static_cast<float>(light.inner_radius_rad), angle);
    out += weight * light.rgb.cast<float>();
  }
  return out;
}

cv::Mat EnvironmentMap::Picture(int width) const {
  const int height = width / 2;
  cv::Mat picture(height, width, CV_8UC3);
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      // Longitude across the half-space in front of the face (toward the camera, -z).
      const double longitude = (col + 0.5) / width * M_PI - M_PI / 2;
      const double latitude = (row + 0.5) / height * M_PI - M_PI / 2;
      const Eigen::Vector3f direction(static_cast<float>(std::sin(longitude) * std::cos(latitude)),
                                      static_cast<float>(std::sin(latitude)),
                                      static_cast<float>(-std::cos(longitude) * std::cos(latitude)));
      const Eigen::Vector3f rgb = Radiance(direction);
      auto tone = [](float v) { return cv::saturate_cast<uchar>(255.0f * std::pow(v / (1.0f + v), 0.6f)); };
      picture.at<cv::Vec3b>(row, col) = {tone(rgb.z()), tone(rgb.y()), tone(rgb.x())};
    }
  }
  return picture;
}

const std::array<EnvironmentMap, 5>& BuiltInEnvironmentMaps() {
  // Directions point from the eye toward the light: -z is toward the camera,
  // -y is up.
  static const std::array<EnvironmentMap, 5> maps = [] {
    const Eigen::Vector3d warm(1.0, 0.92, 0.8), cool(0.85, 0.92, 1.0);
    std::array<EnvironmentMap, 5> m;
    m[0].name = "window-left";
    m[0].lights = {Light({-0.55, -0.35, -1}, 0.22, 0.08, 6.0, cool), Light({0.6, -0.2, -1}, 0.5, 0.3, 0.4)};
    m[1].name = "window-right";
    m[1].lights = {Light({0.55, -0.35, -1}, 0.22, 0.08, 6.0, cool), Light({-0.6, -0.2, -1}, 0.5, 0.3, 0.4)};
    m[2].name = "overhead";
    m[2].lights = {Light({0, -1, -0.55}, 0.35, 0.15, 5.0, warm)};
    m[3].name = "ring-light";
    m[3].lights = {Light({0, 0, -1}, 0.16, 0.03, 8.0, Eigen::Vector3d::Ones(), 0.11)};
    m[4].name = "softbox-front";
    m[4].lights = {Light({0.12, -0.25, -1}, 0.14, 0.06, 7.0, warm), Light({-0.3, 0.1, -1}, 0.6, 0.4, 0.3)};
    for (auto& map : m) map.surround = Eigen::Vector3d::Constant(0.03);
    return m;
  }();
  return maps;
}

}  // namespace gazedirector
