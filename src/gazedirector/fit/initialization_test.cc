#include "gazedirector/fit/initialization.h"

#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::SharedModel;

// The paper's initialisation on real faces: the model's four eye corners land
// on the landmarked ones. Only the translation is fitted, at the average
// interocular distance, so people whose eyes sit wider or closer apart than
// 63 mm keep a residual of a few per cent of their interocular distance; a
// swapped eye or corner would miss by half of it.
TEST(InitializationTest, TheModelsEyeCornersLandOnTheLandmarkedCorners) {
  for (const char* photo : {"images/d30.jpg", "images/d19.jpg", "images/s42.jpg"}) {
    const testing::DetectedStill still = testing::DetectStill(photo);
    ASSERT_EQ(still.faces.size(), 1u) << photo;
    const Face& face = still.faces[0];
    const Camera& camera = still.camera;
    const Parameters phi = InitializeFromLandmarks(face, camera, *SharedModel());
    double squared = 0;
    for (int eye = 0; eye < 2; ++eye) {
      const auto corners = ModelEyeCorners(phi, *SharedModel(), eye);
      for (int corner = 0; corner < 2; ++corner) {
        squared += (camera.Project(corners[corner]) - face.landmarks[kCornerLandmarks[eye][corner]]).squaredNorm();
      }
    }
    const double rms = std::sqrt(squared / 4);
    EXPECT_LT(rms, 0.05 * face.InterocularDistance()) << photo << ": " << rms << " px";
    // Everything but the pose starts at its mean.
    EXPECT_EQ(phi.shape().norm(), 0) << photo;
    EXPECT_EQ(phi.texture().norm(), 0) << photo;
    EXPECT_EQ(phi.gaze_pitch(), 0) << photo;
    EXPECT_EQ(phi.gaze_yaw(), 0) << photo;
    EXPECT_EQ(phi.interocular(), kAverageInterocularMm) << photo;
  }
}

// Where the four corners are reachable exactly (they were projected from a
// known Φ), the corner fit finds Φ's translation again from a start 40 mm off.
TEST(InitializationTest, TheCornerFitRecoversAKnownTranslation) {
  const Camera camera = Camera::Default(640, 480);
  Parameters truth;
  truth.interocular() = kAverageInterocularMm;
  truth.set_rotation(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()).toRotationMatrix());
  truth.block<Block::kTranslation>() = Eigen::Vector3d(12, -8, 450);
  std::vector<CornerTarget> targets;
  for (int eye = 0; eye < 2; ++eye) {
    const auto corners = ModelEyeCorners(truth, *SharedModel(), eye);
    for (int corner = 0; corner < 2; ++corner) targets.push_back({eye, corner, camera.Project(corners[corner])});
  }
  Parameters start = truth;
  start.block<Block::kTranslation>() += Eigen::Vector3d(-15, 10, 35);
  const Eigen::Vector3d found = FitTranslationToCorners(start, *SharedModel(), camera, targets);
  EXPECT_LT((found - truth.translation()).norm(), 0.01) << found.transpose();
}

}  // namespace
}  // namespace gazedirector
