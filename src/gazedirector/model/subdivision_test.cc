#include "gazedirector/model/subdivision.h"

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "gazedirector/io/obj_reader.h"
#include "gazedirector/model/eye_region_topology.h"
#include "gazedirector/util/error.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;

fs::path SubdivisionDir() { return testing::TestAssets().eye_model() / "subdivision"; }

Subdivision EyeRegionSubdivision() {
  return Subdivision::Load(SubdivisionDir(), "eye_region", topology::kNumRegionVertices);
}

ObjMesh RestMesh() { return ReadObj(testing::TestAssets().eye_model() / "mesh" / "eye_region.obj"); }

TEST(SubdivisionTest, ReproducesTheAssetsSubdividedRestShape) {
  const Subdivision subdivision = EyeRegionSubdivision();
  EXPECT_EQ(subdivision.num_vertices(), 872);
  EXPECT_EQ(subdivision.triangles().size(), 1656u);
  const Eigen::Matrix3Xd rest = RestMesh().PositionsMm();
  Eigen::Matrix3Xd subdivided;
  subdivision.Apply(rest, subdivided);
  const auto reference = ReadNumberTable(SubdivisionDir() / "new_verts_eye_region.txt");
  ASSERT_EQ(reference.size(), 872u);
  double total = 0;
  for (int i = 0; i < 872; ++i) {
    // Stored as (-x, -z, y) in metres.
    const Eigen::Vector3d expected(-1000 * reference[i][0], 1000 * reference[i][2], -1000 * reference[i][1]);
    total += (subdivided.col(i) - expected).norm();
  }
  EXPECT_LT(total / 872, 0.05) << "mean distance in mm";
}

// The same stencils serve the texture coordinates (two rows) and the
// positions (three), in single or double precision.
TEST(SubdivisionTest, AppliesTheSameStencilsToEveryRowCountAndPrecision) {
  const Subdivision subdivision = EyeRegionSubdivision();
  const ObjMesh mesh = RestMesh();
  const auto count = static_cast<Eigen::Index>(mesh.uvs.size());
  Eigen::Matrix2Xd uvs(2, count);
  Eigen::Matrix3Xd padded = Eigen::Matrix3Xd::Zero(3, count);
  for (Eigen::Index i = 0; i < count; ++i) {
    uvs.col(i) = mesh.uvs[i];
    padded.col(i).head<2>() = mesh.uvs[i];
  }
  const Eigen::Matrix3Xf single = mesh.PositionsMm().cast<float>();
  Eigen::Matrix2Xd fine_uvs;
  Eigen::Matrix3Xd fine_padded;
  subdivision.Apply(uvs, fine_uvs);
  subdivision.Apply(padded, fine_padded);
  ASSERT_EQ(fine_uvs.cols(), 872);
  EXPECT_LT((fine_uvs - fine_padded.topRows<2>()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT(fine_padded.row(2).cwiseAbs().maxCoeff(), 1e-15);

  Eigen::Matrix3Xf fine_single;
  Eigen::Matrix3Xd fine_double;
  subdivision.Apply(single, fine_single);
  subdivision.Apply(Eigen::Matrix3Xd(single.cast<double>()), fine_double);
  EXPECT_LT((fine_single.cast<double>() - fine_double).cwiseAbs().maxCoeff(), 1e-4) << "mm";
  // A field that is the same everywhere stays so: each stencil's weights sum to 1.
  Eigen::Matrix3Xd fine_constant;
  subdivision.Apply(Eigen::Matrix3Xd(Eigen::Matrix3Xd::Constant(3, count, 7.0)), fine_constant);
  EXPECT_LT((fine_constant.array() - 7.0).abs().maxCoeff(), 7e-4);
}

// Broken stencil files are the user's assets to mend: exit code 5 and what
// is wrong, never an index past the mesh.
TEST(SubdivisionTest, BrokenStencilsFailWithTheAssetsCode) {
  const struct {
    std::string name, indices, weights, triangles, says;
  } cases[] = {
      {"rows", "0 1\n1 2\n", "0.5 0.5\n", "0\n1\n0\n", "mismatched rows"},
      {"sum", "0 1\n1 2\n", "0.5 0.5\n0.5 0.4\n", "0\n1\n0\n", "stencil 1 weights sum to 0.9"},
      {"index", "0 1\n1 3\n", "0.5 0.5\n0.5 0.5\n", "0\n1\n0\n", "stencil index out of range"},
      {"ragged", "0 1\n1\n", "0.5 0.5\n0.5 0.5\n", "0\n1\n0\n", "stencil 1 is malformed"},
      {"thirds", "0 1\n1 2\n", "0.5 0.5\n0.5 0.5\n", "0\n1\n", "not a multiple of 3"},
      {"far", "0 1\n1 2\n", "0.5 0.5\n0.5 0.5\n", "0\n1\n2\n", "subdivided triangle index out of range"},
  };
  for (const auto& c : cases) {
    const fs::path dir = testing::ScratchDir("subdivision_" + c.name);
    std::ofstream(dir / "new_v_idxs_test.txt") << c.indices;
    std::ofstream(dir / "new_v_weights_test.txt") << c.weights;
    std::ofstream(dir / "new_tris_test.txt") << c.triangles;
    try {
      Subdivision::Load(dir, "test", 3);
      ADD_FAILURE() << c.name << ": loaded";
    } catch (const Error& error) {
      EXPECT_EQ(error.code(), ExitCode::kAssets) << c.name;
      EXPECT_NE(std::string(error.what()).find(c.says), std::string::npos) << c.name << ": " << error.what();
    }
  }
  // The well-formed version of the same files loads: two new vertices, one triangle.
  const fs::path dir = testing::ScratchDir("subdivision_good");
  std::ofstream(dir / "new_v_idxs_test.txt") << "0 1\n1 2\n";
  std::ofstream(dir / "new_v_weights_test.txt") << "0.5 0.5\n0.5 0.5\n";
  std::ofstream(dir / "new_tris_test.txt") << "0\n1\n0\n";
  const Subdivision good = Subdivision::Load(dir, "test", 3);
  EXPECT_EQ(good.num_vertices(), 2);
  EXPECT_EQ(good.triangles().size(), 1u);
}

}  // namespace
}  // namespace gazedirector
