#include "gazedirector/fit/landmark_model.h"

#include <map>
#include <set>

#include <gtest/gtest.h>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::SharedModel;

// The 24 landmarks the energy compares: each a distinct dlib point, each an
// affine combination of vertices (weights summing to one, so the landmark
// moves with the mesh as a point on it does), the lid points of one eye only.
TEST(LandmarkModelTest, TwentyFourDistinctPointsEachAnAffineCombinationOfVertices) {
  const LandmarkModel landmarks(*SharedModel());
  ASSERT_EQ(landmarks.landmarks().size(), 24u);
  std::set<int> indices;
  std::map<LandmarkGroup, int> groups;
  for (const ModelLandmark& landmark : landmarks.landmarks()) {
    indices.insert(landmark.dlib_index);
    ++groups[landmark.group];
    double sum = 0;
    std::set<int> eyes;
    for (const auto& term : landmark.terms) {
      sum += term.weight;
      eyes.insert(term.eye);
      EXPECT_GE(term.weight, 0) << "landmark " << landmark.dlib_index;
    }
    EXPECT_NEAR(sum, 1.0, 1e-12) << "landmark " << landmark.dlib_index;
    EXPECT_EQ(eyes.size(), landmark.group == LandmarkGroup::kNose ? 2u : 1u) << "landmark " << landmark.dlib_index;
  }
  EXPECT_EQ(indices.size(), 24u);
  EXPECT_EQ(groups[LandmarkGroup::kEyelid], 12);
  EXPECT_EQ(groups[LandmarkGroup::kBrow], 10);
  EXPECT_EQ(groups[LandmarkGroup::kNose], 2);
}

// The eye-centre point that frames an eye-patch fit is the mean of that
// eye's six lid and corner landmarks.
TEST(LandmarkModelTest, TheEyeCentreIsTheMeanOfTheEyesSixLandmarks) {
  const LandmarkModel landmarks(*SharedModel());
  Parameters phi;
  phi.block<Block::kTranslation>() = Eigen::Vector3d(5, -3, 400);
  phi.gaze_pitch() = -10;
  phi.eyelid_pitch() = -10;
  PosedModel posed;
  PoseWorkspace workspace;
  SharedModel()->Pose(phi, posed, workspace);
  const Camera camera = Camera::Default(640, 480);
  std::vector<Eigen::Vector2d> all, centre;
  landmarks.Project(posed, camera, all);
  for (int eye = 0; eye < 2; ++eye) {
    Eigen::Vector3d mean_point = Eigen::Vector3d::Zero();
    for (const ModelLandmark& landmark : landmarks.landmarks()) {
      if (landmark.group != LandmarkGroup::kEyelid || landmark.terms.front().eye != eye) continue;
      for (const auto& term : landmark.terms) {
        const PosedEye& posed_eye = posed.eyes[eye];
        mean_point += term.weight / 6 * (posed_eye.region_to_camera * posed.region[eye].col(term.vertex) + posed_eye.centre);
      }
    }
    landmarks.EyeCentre(eye).Project(posed, camera, centre);
    ASSERT_EQ(centre.size(), 1u);
    EXPECT_LT((centre[0] - camera.Project(mean_point)).norm(), 1e-9) << "eye " << eye;
  }
}

// On a real face the fitted model's lid and corner landmarks sit on dlib's:
// each within 4% of the interocular distance, where an upper lid point
// matched to a lower one would be off by the eye's opening.
TEST(LandmarkModelTest, AFittedFacesLidLandmarksSitOnTheTrackersOnes) {
  const testing::FittedStill& still = testing::FitStill("images/d30.jpg");
  ASSERT_EQ(still.faces.size(), 1u);
  const FitResult& fit = still.fit;
  ASSERT_TRUE(fit.good) << fit.note;
  const LandmarkModel landmarks(*SharedModel());
  PosedModel posed;
  PoseWorkspace workspace;
  SharedModel()->Pose(fit.phi, posed, workspace);
  std::vector<Eigen::Vector2d> projected;
  landmarks.Project(posed, still.camera, projected);
  const double interocular = still.faces[0].InterocularDistance();
  for (std::size_t k = 0; k < projected.size(); ++k) {
    const ModelLandmark& landmark = landmarks.landmarks()[k];
    if (landmark.group != LandmarkGroup::kEyelid) continue;
    const double miss = (projected[k] - still.faces[0].landmarks[landmark.dlib_index]).norm();
    EXPECT_LT(miss, 0.04 * interocular) << "dlib landmark " << landmark.dlib_index << ": " << miss << " px";
  }
}

}  // namespace
}  // namespace gazedirector
