#include "gazedirector/model/shape_model.h"

#include <gtest/gtest.h>

#include "gazedirector/io/obj_reader.h"
#include "gazedirector/model/subdivision.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;

fs::path EyeModelDir() { return testing::TestAssets().eye_model(); }

Eigen::Matrix3Xd PositionsMm(const ObjMesh& mesh) {
  Eigen::Matrix3Xd positions(3, mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) positions.col(static_cast<Eigen::Index>(i)) = 1000.0 * mesh.positions[i];
  return positions;
}

TEST(ShapeModelTest, ReconstructsEveryRegisteredSubjectToAMillimetre) {
  const ShapeModel model = ShapeModel::Load(EyeModelDir() / "shape", 16);
  int subjects = 0;
  for (const auto& entry : fs::directory_iterator(EyeModelDir() / "mesh" / "registered_subjects")) {
    const Eigen::Matrix3Xd subject = PositionsMm(ReadObj(entry.path()));
    const Eigen::VectorXd beta = model.Project(subject);
    Eigen::Matrix3Xd reconstructed;
    model.Evaluate(beta.data(), reconstructed);
    const double mean_error = (reconstructed - subject).colwise().norm().mean();
    EXPECT_LT(mean_error, 1.0) << entry.path().filename();
    EXPECT_LT(beta.cwiseAbs().maxCoeff(), 4.0) << "coefficients are in standard deviations";
    ++subjects;
  }
  EXPECT_EQ(subjects, 8);
  // With no modes the error is the subjects' spread: the PCA explains most of it.
  const ShapeModel mean_only = ShapeModel::Load(EyeModelDir() / "shape", 1);
  EXPECT_EQ(mean_only.num_modes(), 1);
}

TEST(ShapeModelTest, ModesMoveVerticesByTheirStandardDeviation) {
  const ShapeModel model = ShapeModel::Load(EyeModelDir() / "shape", 16);
  std::vector<double> beta(16, 0.0);
  Eigen::Matrix3Xd mean, moved;
  model.Evaluate(beta.data(), mean);
  EXPECT_LT((mean - model.mean()).norm(), 1e-12);
  beta[0] = 1.0;
  model.Evaluate(beta.data(), moved);
  // The first mode's deviation is 32.85 mm over all 687 coordinates (unit-norm component).
  EXPECT_NEAR((moved - mean).norm(), 32.85, 0.1);
}

TEST(SubdivisionTest, ReproducesTheAssetsSubdividedRestShape) {
  const Subdivision subdivision = Subdivision::Load(EyeModelDir() / "subdivision", "eye_region", 229);
  EXPECT_EQ(subdivision.num_vertices(), 872);
  EXPECT_EQ(subdivision.triangles().size(), 1656u);
  const Eigen::Matrix3Xd rest = PositionsMm(ReadObj(EyeModelDir() / "mesh" / "eye_region.obj"));
  Eigen::Matrix3Xd subdivided;
  subdivision.Apply(rest, subdivided);
  const auto reference = ReadNumberTable(EyeModelDir() / "subdivision" / "new_verts_eye_region.txt");
  ASSERT_EQ(reference.size(), 872u);
  double total = 0;
  for (int i = 0; i < 872; ++i) {
    // Stored as (-x, -z, y) in metres.
    const Eigen::Vector3d expected(-1000 * reference[i][0], 1000 * reference[i][2], -1000 * reference[i][1]);
    total += (subdivided.col(i) - expected).norm();
  }
  EXPECT_LT(total / 872, 0.05) << "mean distance in mm";
}

}  // namespace
}  // namespace gazedirector
