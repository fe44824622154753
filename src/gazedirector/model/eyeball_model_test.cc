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

}  // namespace
}  // namespace gazedirector
