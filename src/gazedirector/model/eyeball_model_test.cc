#include "gazedirector/model/eyeball_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Geometry>

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

Eigen::Vector3d FaceNormal(const EyeballModel& eyeball, const Eigen::Vector3i& t) {
  const Eigen::Matrix3Xd& p = eyeball.positions();
  return (p.col(t[1]) - p.col(t[0])).cross(p.col(t[2]) - p.col(t[0])).normalized();
}

TEST(EyeballModelTest, PatchesCoverEveryTriangleOnceWithinTheirBounds) {
  const EyeballModel& eyeball = Eyeball();
  int next = 0;
  for (const EyeballPatch& patch : eyeball.patches()) {
    ASSERT_EQ(patch.begin, next);
    ASSERT_GT(patch.end, patch.begin);
    next = patch.end;
    for (int i = patch.begin; i < patch.end; ++i) {
      const Eigen::Vector3i& t = eyeball.triangles()[i];
      for (int k = 0; k < 3; ++k) EXPECT_LE((eyeball.positions().col(t[k]) - patch.centre).norm(), patch.radius + 1e-9);
      const double cosine = FaceNormal(eyeball, t).dot(patch.axis);
      // Within the cone, whose sine is kept (above 1: no bound).
      if (patch.cone_sine <= 1) {
        EXPECT_GE(cosine, std::sqrt(1 - patch.cone_sine * patch.cone_sine) - 1e-9);
      }
    }
  }
  EXPECT_EQ(next, static_cast<int>(eyeball.triangles().size()));
  EXPECT_GE(eyeball.patches().size(), 24u);
}

// No triangle of a patch said to face away faces the camera, and from in
// front of the eye at a working distance the patches facing away hold the
// back of the eyeball.
TEST(EyeballModelTest, PatchesFacingAwayHoldOnlyTrianglesFacingAway) {
  const EyeballModel& eyeball = Eyeball();
  std::mt19937 random(5);
  std::normal_distribution<double> direction(0.0, 1.0);
  std::uniform_real_distribution<double> distance(15.0, 800.0);
  int culled = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d camera =
        Eigen::Vector3d(direction(random), direction(random), direction(random)).normalized() * distance(random);
    for (const EyeballPatch& patch : eyeball.patches()) {
      if (!patch.FacesAwayFrom(camera)) continue;
      for (int i = patch.begin; i < patch.end; ++i) {
        const Eigen::Vector3i& t = eyeball.triangles()[i];
        for (int k = 0; k < 3; ++k) {
          ASSERT_GT(FaceNormal(eyeball, t).dot(eyeball.positions().col(t[k]) - camera), 0) << "trial " << trial;
        }
        ++culled;
      }
    }
  }
  EXPECT_GT(culled, 200 * 0.25 * static_cast<double>(eyeball.triangles().size()));
  int ahead = 0;  // the eyeball looks along -y
  for (const EyeballPatch& patch : eyeball.patches()) {
    if (patch.FacesAwayFrom(Eigen::Vector3d(0, -400, 0))) ahead += patch.end - patch.begin;
  }
  EXPECT_GT(ahead, static_cast<int>(eyeball.triangles().size()) / 4);
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
