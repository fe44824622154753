#include "gazedirector/redirect/environment_map.h"

#include <set>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

namespace gazedirector {
namespace {

const EnvironmentMap& Map(const std::string& name) {
  for (const EnvironmentMap& map : BuiltInEnvironmentMaps()) {
    if (map.name == name) return map;
  }
  throw std::runtime_error("no map " + name);
}

Eigen::Vector3f Toward(const AreaLight& light, double off_rad) {
  const Eigen::Vector3d side = light.direction.unitOrthogonal();
  return (std::cos(off_rad) * light.direction + std::sin(off_rad) * side).cast<float>();
}

TEST(EnvironmentMapTest, EveryBuiltInMapHasItsOwnNameAndLightsInFrontOfTheFace) {
  std::set<std::string> names;
  for (const EnvironmentMap& map : BuiltInEnvironmentMaps()) {
    EXPECT_TRUE(names.insert(map.name).second) << map.name;
    ASSERT_FALSE(map.lights.empty()) << map.name;
    for (const AreaLight& light : map.lights) {
      EXPECT_NEAR(light.direction.norm(), 1.0, 1e-12);
      EXPECT_LT(light.direction.z(), 0.0) << map.name << ": lights the eyes from the camera's side";
      EXPECT_GT(light.rgb.minCoeff(), 0.0);
    }
  }
}

// Each light is its full radiance over its core, fades over its feather,
// and leaves only the surround beyond it.
TEST(EnvironmentMapTest, ALightIsBrightInItsCoreAndGoneBeyondItsFeather) {
  const EnvironmentMap& map = Map("overhead");
  ASSERT_EQ(map.lights.size(), 1u);
  const AreaLight& light = map.lights.front();
  const Eigen::Vector3f surround = map.surround.cast<float>();
  const Eigen::Vector3f full = surround + light.rgb.cast<float>();
  EXPECT_LT((map.Radiance(Toward(light, 0)) - full).norm(), 1e-5);
  EXPECT_LT((map.Radiance(Toward(light, 0.9 * light.radius_rad)) - full).norm(), 1e-5);
  const Eigen::Vector3f edge = map.Radiance(Toward(light, light.radius_rad + 0.5 * light.feather_rad));
  EXPECT_NEAR((edge - surround).norm() / light.rgb.cast<float>().norm(), 0.5, 1e-4) << "halfway through the feather";
  EXPECT_LT((map.Radiance(Toward(light, light.radius_rad + 1.01 * light.feather_rad)) - surround).norm(), 1e-6);
  EXPECT_LT((map.Radiance(-light.direction.cast<float>()) - surround).norm(), 1e-6);
}

// A ring light reflects as a ring: dark in its middle, bright at its radius.
TEST(EnvironmentMapTest, ARingLightIsDarkInItsMiddle) {
  const EnvironmentMap& map = Map("ring-light");
  const AreaLight& ring = map.lights.front();
  ASSERT_GT(ring.inner_radius_rad, 0.0);
  const float middle = map.Radiance(Toward(ring, 0)).x();
  const float on_ring = map.Radiance(Toward(ring, 0.5 * (ring.inner_radius_rad + ring.radius_rad))).x();
  EXPECT_LT(middle, map.surround.x() + 1e-6);
  EXPECT_NEAR(on_ring, map.surround.x() + ring.rgb.x(), 1e-4);
}

// The picture people look at in --debug-dir puts each light where it is: a
// window on the left in the picture's left half, an overhead light at its top.
TEST(EnvironmentMapTest, ThePictureShowsEachLightOnItsSide) {
  auto brightest = [](const cv::Mat& picture) {
    cv::Mat grey;
    cv::transform(picture, grey, cv::Matx13f(1.0f / 3, 1.0f / 3, 1.0f / 3));
    cv::Point at;
    cv::minMaxLoc(grey, nullptr, nullptr, nullptr, &at);
    return at;
  };
  const cv::Mat left = Map("window-left").Picture(256);
  ASSERT_EQ(left.size(), cv::Size(256, 128));
  ASSERT_EQ(left.type(), CV_8UC3);
  EXPECT_LT(brightest(left).x, 128);
  EXPECT_GT(brightest(Map("window-right").Picture(256)).x, 128);
  EXPECT_LT(brightest(Map("overhead").Picture(256)).y, 32);
}

}  // namespace
}  // namespace gazedirector
