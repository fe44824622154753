#include "gazedirector/render/limbus_distance.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <utility>

#include <gtest/gtest.h>

#include "gazedirector/model/eye_region_topology.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::SharedModel;

// The distance is about zero on the projected limbus ring, and grows by a
// pixel per pixel along the iris's radius: checked 3 px out and in from
// each ring vertex that shows, looking ahead, aside and up (irises about 18 px
// across). The edge the texture draws lies 0.5-0.7 px inside the ring on
// average (likely the cornea's refraction of the uvs just inside it), about
// as much as rounding each point to its pixel may move it.
TEST(LimbusDistanceTest, IsAboutZeroOnTheProjectedLimbusAndGrowsAPixelPerPixel) {
  const Camera camera{1200, 1200, 199.5, 99.5, 400, 200};
  Renderer renderer(SharedModel());
  RenderBuffers buffers;
  for (const auto& [pitch, yaw] : {std::pair(0.0, 0.0), std::pair(0.0, 20.0), std::pair(15.0, 0.0)}) {
    Parameters phi;
    phi.block<Block::kTranslation>() = Eigen::Vector3d(0, 0, 390);
    phi.gaze_pitch() = pitch, phi.gaze_yaw() = yaw;
    renderer.Render(phi, camera, buffers);
    const cv::Mat distance = LimbusDistance(buffers, *SharedModel(), renderer.posed());
    auto at = [&](const Eigen::Vector2d& p, int part) -> std::optional<double> {
      const cv::Point q(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
      if (!cv::Rect(0, 0, distance.cols, distance.rows).contains(q)) return std::nullopt;
      if (buffers.PartAt(q.y * distance.cols + q.x) != part) return std::nullopt;  // under a lid
      return distance.at<float>(q);
    };
    int checked = 0;
    double on_ring = 0, outward_slope = 0, inward_slope = 0;
    for (int part : {kLeftEyeball, kRightEyeball}) {
      const Eigen::Matrix3Xf& positions = renderer.posed().parts[part].positions;
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (int v : topology::kLimbus) centre += positions.col(v).cast<double>();
      const Eigen::Vector2d middle = camera.Project(centre / static_cast<double>(topology::kLimbus.size()));
      for (int v : topology::kLimbus) {
        const Eigen::Vector2d on = camera.Project(positions.col(v).cast<double>());
        const Eigen::Vector2d outward = (on - middle).normalized();
        const auto d_on = at(on, part), d_out = at(on + 3 * outward, part), d_in = at(on - 3 * outward, part);
        if (!d_on || !d_out || !d_in) continue;
        ++checked;
        on_ring += *d_on, outward_slope += (*d_out - *d_on) / 3, inward_slope += (*d_on - *d_in) / 3;
      }
    }
    ASSERT_GT(checked, 20);
    on_ring /= checked, outward_slope /= checked, inward_slope /= checked;
    std::printf("pitch %+.0f yaw %+.0f, %d ring vertices: %.2f px on the ring, %.2f / %.2f px per px out / in\n",
                pitch, yaw, checked, on_ring, outward_slope, inward_slope);
    EXPECT_GT(on_ring, -0.2);
    EXPECT_LT(on_ring, 1.0);
    EXPECT_NEAR(outward_slope, 1.0, 0.15);
    EXPECT_NEAR(inward_slope, 1.0, 0.15);
  }
}

}  // namespace
}  // namespace gazedirector
