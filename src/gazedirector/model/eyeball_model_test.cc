#include "gazedirector/model/eyeball_model.h"

#include <gtest/gtest.h>

#include "gazedirector/model/eye_region_topology.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

const EyeballModel& Eyeball() {
  static const EyeballModel eyeball = EyeballModel::Load(testing::TestAssets().eye_model() / "mesh" / "eyeball.obj");
  return eyeball;
}

void ExpectMirror(const std::vector<int>& mirrored, const Eigen::Vector3d& flip) {
  const EyeballModel& eyeball = Eyeball();
  ASSERT_EQ(static_cast<int>(mirrored.size()), eyeball.num_vertices());
  for (int v = 0; v < eyeball.num_vertices(); ++v) {
    const int image = mirrored[v];
    // Twice mirrored comes back (to v or a vertex at the same place: the uv seam doubles some).
    EXPECT_LT((eyeball.positions().col(mirrored[image]) - eyeball.positions().col(v)).norm(), 0.01);
    EXPECT_LT((eyeball.positions().col(image) - eyeball.positions().col(v).cwiseProduct(flip)).norm(), 0.01);
  }
}

TEST(EyeballModelTest, MirrorImagesAcrossTheVerticalAndHorizontalPlanesAreVertices) {
  ExpectMirror(Eyeball().mirrored_across_x(), Eigen::Vector3d(-1, 1, 1));
  ExpectMirror(Eyeball().mirrored_across_z(), Eigen::Vector3d(1, 1, -1));
}

TEST(EyeballModelTest, TheLimbusMirrorsOntoItselfAndOffTheAxisVerticesMove) {
  const EyeballModel& eyeball = Eyeball();
  const std::vector<int>& across_x = eyeball.mirrored_across_x();
  for (int v : topology::kLimbus) {
    EXPECT_NE(std::find(topology::kLimbus.begin(), topology::kLimbus.end(), across_x[v]), topology::kLimbus.end());
  }
  int moved = 0;
  for (int v = 0; v < eyeball.num_vertices(); ++v) moved += across_x[v] != v;
  EXPECT_GT(moved, eyeball.num_vertices() / 2);
}

TEST(EyeballModelTest, BatchedRefractionMatchesOneRayAtATime) {
  const EyeballModel& eyeball = Eyeball();
  for (const Eigen::Vector3d& camera : {Eigen::Vector3d(0, -600, 0), Eigen::Vector3d(150, -400, -90)}) {
    for (double iris_size : {0.9, 1.1}) {
      Eigen::Matrix2Xf uvs = Eigen::Matrix2Xf::Constant(2, eyeball.num_vertices(), -1.0f);
      eyeball.RefractedUvs(camera, iris_size, uvs);
      for (int v = 0; v < eyeball.num_vertices(); ++v) {
        if (!eyeball.is_cornea()[v]) {
          EXPECT_EQ(uvs(0, v), -1.0f) << "vertex " << v << " is not on the cornea";
          continue;
        }
        const Eigen::Vector3d view = (eyeball.positions().col(v) - camera).normalized();
        const Eigen::Vector2f expected = eyeball.RefractedUv(v, view, iris_size).cast<float>();
        EXPECT_NEAR(uvs(0, v), expected.x(), 1e-6) << "vertex " << v;
        EXPECT_NEAR(uvs(1, v), expected.y(), 1e-6) << "vertex " << v;
      }
    }
  }
}

}  // namespace
}  // namespace gazedirector
