#include "gazedirector/render/rasterizer.h"

#include <random>

#include <gtest/gtest.h>

#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/render/renderer.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

// A square of two triangles covering [2.5, 12.5] x [2.5, 12.5] on a 16x16 target.
std::vector<ScreenVertex> Square(float z) {
  return {SnapVertex(2.5f, 2.5f, z), SnapVertex(12.5f, 2.5f, z), SnapVertex(12.5f, 12.5f, z), SnapVertex(2.5f, 12.5f, z)};
}
// Counter-clockwise seen from outside means clockwise on the y-down screen.
const std::vector<Eigen::Vector3i> kSquareTriangles = {{0, 2, 1}, {0, 3, 2}};

TEST(RasterizerTest, SharedEdgesAreWatertightWithoutOverlap) {
  VisibilityBuffer buffer;
  buffer.Reset(16, 16);
  const auto vertices = Square(100);
  buffer.Draw(vertices.data(), kSquareTriangles.data(), 2, 0);
  int covered = 0;
  for (int i = 0; i < buffer.size(); ++i) covered += buffer.covered(i);
  EXPECT_EQ(covered, 100) << "pixel centres 3..12 in x and y, each exactly once";
  // The diagonal pixels belong to exactly one of the two triangles.
  EXPECT_TRUE(buffer.covered(5 * 16 + 5));
}

TEST(RasterizerTest, BackFacesAreCulledAndTheNearerSurfaceWins) {
  VisibilityBuffer buffer;
  buffer.Reset(16, 16);
  const std::vector<Eigen::Vector3i> reversed = {{0, 1, 2}, {0, 2, 3}};
  const auto far = Square(200), near = Square(100);
  buffer.Draw(far.data(), reversed.data(), 2, 0);
  EXPECT_FALSE(buffer.covered(7 * 16 + 7)) << "a triangle seen from behind draws nothing";
  buffer.Draw(near.data(), kSquareTriangles.data(), 2, 10);
  buffer.Draw(far.data(), kSquareTriangles.data(), 2, 20);
  EXPECT_LT(buffer.triangle(7 * 16 + 7), 20);
  EXPECT_FLOAT_EQ(buffer.depth(7 * 16 + 7), 100.0f);
}

TEST(RasterizerTest, BarycentricsReproduceThePixelPosition) {
  VisibilityBuffer buffer;
  buffer.Reset(16, 16);
  // Each vertex's x, y and depth, as a column.
  Eigen::Matrix3f xyz;
  xyz << 1, 14, 4, 1, 3, 13, 10, 20, 30;
  std::vector<ScreenVertex> v;
  for (int i = 0; i < 3; ++i) v.push_back(SnapVertex(xyz(0, i), xyz(1, i), xyz(2, i)));
  // Clockwise on screen: (a, c, b) as stored order a, b, c must give positive Edge(a, b, c).
  const std::vector<Eigen::Vector3i> triangle = {{0, 2, 1}};
  buffer.Draw(v.data(), triangle.data(), 1, 0);
  int checked = 0;
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      const int pixel = y * 16 + x;
      if (!buffer.covered(pixel)) continue;
      const Eigen::Vector3f at_pixel = buffer.Interpolate(pixel, xyz, triangle[0]);
      EXPECT_NEAR(at_pixel.x(), x, 1e-4);
      EXPECT_NEAR(at_pixel.y(), y, 1e-4);
      EXPECT_NEAR(buffer.depth(pixel), at_pixel.z(), 1e-3);
      ++checked;
    }
  }
  EXPECT_GT(checked, 40);
}

// Projecting eight vertices at a time snaps exactly as SnapVertex does one
// at a time, also where the coordinates clamp or round half away from zero.
TEST(RasterizerTest, ProjectedVerticesMatchSnappingEachOne) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> lateral(-80.0f, 80.0f), depth(20.0f, 900.0f);
  // First (so that they take the vector path) a clamped point, the principal
  // point and a half-pixel coordinate; the count leaves a scalar tail.
  std::vector<float> xyz = {1e6f, -1e6f, 1.5f, 0.0f, 0.0f, 600.0f, -0.5f / 600.0f * 300.0f, 0.75f, 300.0f};
  for (int i = 0; i < 1000; ++i) xyz.insert(xyz.end(), {lateral(random), lateral(random), depth(random)});
  const int count = static_cast<int>(xyz.size() / 3);
  const float fx = 600, fy = 610, cx = 99.5f, cy = 49.5f;
  std::vector<ScreenVertex> projected(count);
  ProjectVertices(xyz.data(), count, fx, fy, cx, cy, projected.data());
  for (int i = 0; i < count; ++i) {
    const float x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2];
    const float inverse_z = 1.0f / z;
    // Rounded before the additions, as rasterizer.cc computes (this file may fuse a multiply-add).
    const volatile float scaled_x = fx * x * inverse_z, scaled_y = fy * y * inverse_z;
    const ScreenVertex expected = SnapVertex(scaled_x + cx, scaled_y + cy, z);
    ASSERT_EQ(projected[i].x, expected.x) << "vertex " << i;
    ASSERT_EQ(projected[i].y, expected.y) << "vertex " << i;
    ASSERT_EQ(projected[i].z, expected.z) << "vertex " << i;
  }
  EXPECT_EQ(projected[0].x, 65536 * 16);  // clamped
  EXPECT_EQ(projected[0].y, -65536 * 16);
  EXPECT_EQ(projected[1].x, 1592);  // 99.5 px
  EXPECT_EQ(projected[2].x, 1584);  // 99 px exactly
}

// The vectorized setup, fill and pixel list must give exactly the scalar
// path's, on random triangles of all sizes.
TEST(RasterizerTest, VectorizedPathMatchesTheScalarPathBitForBit) {
  std::mt19937 random(3);
  std::uniform_real_distribution<float> coordinate(-30.0f, 130.0f), depth(50.0f, 60.0f);
  std::vector<ScreenVertex> vertices;
  for (int i = 0; i < 3000; ++i) vertices.push_back(SnapVertex(coordinate(random), coordinate(random), depth(random)));
  std::uniform_int_distribution<int> index(0, 2999);
  std::vector<Eigen::Vector3i> triangles;
  for (int i = 0; i < 1000; ++i) {
    const int a = index(random);
    // Mostly small triangles, some large ones.
    const int b = i % 10 == 0 ? index(random) : std::min(2999, a + 1), c = i % 10 == 0 ? index(random) : std::min(2999, a + 2);
    triangles.emplace_back(a, b, c);
  }
  // And many a few pixels across, like the model's at the scale of a fit.
  std::uniform_real_distribution<float> offset(-3.0f, 3.0f);
  for (int i = 0; i < 2000; ++i) {
    const float x = coordinate(random), y = coordinate(random);
    const int first = static_cast<int>(vertices.size());
    for (int k = 0; k < 3; ++k) vertices.push_back(SnapVertex(x + offset(random), y + offset(random), depth(random)));
    triangles.emplace_back(first, first + 1, first + 2);
  }
  VisibilityBuffer vectorized, scalar;
  vectorized.Reset(100, 100);
  scalar.Reset(100, 100);
  scalar.set_vectorized(false);
  const int count = static_cast<int>(triangles.size()) - 5;  // batches of 8 and 16 end part-full
  vectorized.Draw(vertices.data(), triangles.data(), count, 0, Eigen::Vector4i(5, 0, 90, 99));
  scalar.Draw(vertices.data(), triangles.data(), count, 0, Eigen::Vector4i(5, 0, 90, 99));
  for (int i = 0; i < vectorized.size(); ++i) {
    ASSERT_EQ(vectorized.triangle(i), scalar.triangle(i)) << "pixel " << i;
    if (scalar.covered(i)) {
      ASSERT_EQ(vectorized.depth(i), scalar.depth(i));
      ASSERT_EQ(vectorized.b1(i), scalar.b1(i));
      ASSERT_EQ(vectorized.b2(i), scalar.b2(i));
    }
  }
  std::vector<int> covered, covered_scalar;
  vectorized.CollectCovered(covered);
  scalar.CollectCovered(covered_scalar);
  EXPECT_EQ(covered, covered_scalar);
  EXPECT_GT(covered.size(), 2000u);
}

}  // namespace
}  // namespace gazedirector
