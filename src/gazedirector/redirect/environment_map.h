#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace gazedirector {

// A soft, round light source of an environment map.
struct AreaLight {
  Eigen::Vector3d direction;  // toward the light, camera frame (x right, y down, z forward)
  double radius_rad;          // angular radius of its bright core
  double feather_rad;         // width of its soft edge
  Eigen::Vector3d rgb;        // radiance
  double inner_radius_rad = 0;  // > 0 makes a ring (a ring light)
};

// A lighting environment for the eyes' specular reflections: a dim
// surrounding radiance plus a few soft area lights. The five built-in maps
// stand for common shooting conditions; redirection picks the one that best
// explains the highlights in the photo.
struct EnvironmentMap {
  std::string name;
  Eigen::Vector3d surround = Eigen::Vector3d::Constant(0.02);
  std::vector<AreaLight> lights;

  // RGB radiance arriving from unit direction `direction` (camera frame).
  Eigen::Vector3f Radiance(const Eigen::Vector3f& direction) const;
  // The map as an equirectangular picture of the half-space facing the camera
  // (8-bit BGR, `width` x `width / 2`), for people to look at.
  cv::Mat Picture(int width = 256) const;
};

const std::array<EnvironmentMap, 5>& BuiltInEnvironmentMaps();

}  // namespace gazedirector
