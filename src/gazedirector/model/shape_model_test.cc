#include "gazedirector/model/shape_model.h"

#include <gtest/gtest.h>

#include "gazedirector/io/obj_reader.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;

fs::path EyeModelDir() { return testing::TestAssets().eye_model(); }

TEST(ShapeModelTest, ReconstructsEveryRegisteredSubjectToAMillimetre) {
  const ShapeModel model = ShapeModel::Load(EyeModelDir() / "shape", 16);
  int subjects = 0;
  for (const auto& entry : fs::directory_iterator(EyeModelDir() / "mesh" / "registered_subjects")) {
    const Eigen::Matrix3Xd subject = ReadObj(entry.path()).PositionsMm();
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

}  // namespace
}  // namespace gazedirector
