#include "gazedirector/model/eye_region_model.h"

#include <gtest/gtest.h>

#include "gazedirector/geometry/camera.h"
#include "gazedirector/geometry/rotation.h"
#include "gazedirector/model/eye_region_topology.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::SharedModel;

Parameters Frontal(double distance_mm = 500) {
  Parameters phi;
  phi.block<Block::kTranslation>() = Eigen::Vector3d(0, 0, distance_mm);
  return phi;
}

PosedModel Pose(const Parameters& phi) {
  PosedModel posed;
  PoseWorkspace work;
  SharedModel()->Pose(phi, posed, work);
  return posed;
}

// The centre of the iris (limbus ring) in the camera frame.
Eigen::Vector3d IrisCentre(const PosedModel& posed, int eye) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int v : topology::kLimbus) sum += posed.parts[EyeballPart(eye)].positions.col(v).cast<double>();
  return sum / static_cast<double>(topology::kLimbus.size());
}

TEST(EyeRegionModelTest, GazeMovesTheIrisTheRightWayByTheGeometricAmount) {
  const Camera camera = Camera::Default(640, 480);
  const Parameters ahead = Frontal();
  const PosedModel posed_ahead = Pose(ahead);
  for (int eye = 0; eye < 2; ++eye) {
    const Eigen::Vector2d centre = camera.Project(IrisCentre(posed_ahead, eye));
    Parameters right = ahead, up = ahead;
    right.gaze_yaw() = 15;  // toward the subject's left: image right
    up.gaze_pitch() = 10;
    const Eigen::Vector2d moved_right = camera.Project(IrisCentre(Pose(right), eye));
    const Eigen::Vector2d moved_up = camera.Project(IrisCentre(Pose(up), eye));
    // The iris centre is 10.75 mm from the eyeball centre, 500 mm from the camera.
    const double expected_x = camera.fx * 10.75 * std::sin(DegToRad(15)) / 500;
    const double expected_y = camera.fy * 10.75 * std::sin(DegToRad(10)) / 500;
    EXPECT_NEAR(moved_right.x() - centre.x(), expected_x, 0.05 * expected_x) << "eye " << eye;
    EXPECT_NEAR(moved_right.y(), centre.y(), 0.05 * expected_x);
    EXPECT_NEAR(centre.y() - moved_up.y(), expected_y, 0.05 * expected_y) << "up is -y on the image";
  }
  // The gaze vector points along the same directions.
  EXPECT_GT(Pose([&] { Parameters p = ahead; p.gaze_yaw() = 20; return p; }()).eyes[0].gaze.x(), 0.3);
  EXPECT_LT(posed_ahead.eyes[0].gaze.z(), -0.99) << "looking at the camera";
}

TEST(EyeRegionModelTest, AReusedWorkspaceFollowsEveryChangeOfShape) {
  // The workspace keeps the evaluated shape between poses; a new β must still reach every vertex.
  PosedModel reused;
  PoseWorkspace work;
  Parameters phi = Frontal();
  SharedModel()->Pose(phi, reused, work);
  for (double beta : {2.0, -1.5, 0.0}) {
    phi.shape()[3] = beta;
    phi.gaze_pitch() = beta;
    SharedModel()->Pose(phi, reused, work);
    const PosedModel fresh = Pose(phi);
    for (int part = 0; part < kNumParts; ++part) {
      EXPECT_EQ(reused.parts[part].positions, fresh.parts[part].positions) << "beta " << beta << ", part " << part;
    }
  }
  Parameters other = phi;
  other.shape()[3] = 2.0;
  EXPECT_GT((Pose(other).parts[kLeftSkin].positions - reused.parts[kLeftSkin].positions).cwiseAbs().maxCoeff(), 0.1)
      << "shape mode 3 moves the skin";
}

TEST(EyeRegionModelTest, PitchYawInHeadInvertsGazeInHead) {
  for (double pitch : {-25.0, 0.0, 17.0}) {
    for (double yaw : {-40.0, -3.0, 0.0, 30.0}) {
      const Eigen::Vector2d back = EyeRegionModel::PitchYawInHead(EyeRegionModel::GazeInHead(pitch, yaw));
      EXPECT_NEAR(back.x(), pitch, 1e-9);
      EXPECT_NEAR(back.y(), yaw, 1e-9);
    }
  }
}

TEST(EyeRegionModelTest, VergenceTurnsBothEyesTowardTheNose) {
  Parameters phi = Frontal();
  phi.vergence() = 10;
  const PosedModel posed = Pose(phi);
  // The left eye is at +x (image right): converging turns it toward -x.
  EXPECT_LT(posed.eyes[kLeftEye].gaze.x(), -0.05);
  EXPECT_GT(posed.eyes[kRightEye].gaze.x(), 0.05);
}

TEST(EyeRegionModelTest, TheTwoEyesAreMirrorImages) {
  const PosedModel posed = Pose(Frontal());
  for (int part : {kLeftSkin, kLeftEyeball}) {
    const Eigen::Matrix3Xf& left = posed.parts[part].positions;
    const Eigen::Matrix3Xf& right = posed.parts[part + 1].positions;
    ASSERT_EQ(left.cols(), right.cols());
    for (Eigen::Index i = 0; i < left.cols(); ++i) {
      EXPECT_NEAR(left(0, i), -right(0, i), 1e-3);
      EXPECT_NEAR(left(1, i), right(1, i), 1e-3);
      EXPECT_NEAR(left(2, i), right(2, i), 1e-3);
    }
  }
}

TEST(EyeRegionModelTest, EyelidPitchMovesTheUpperMargin) {
  auto upper_lid_height = [](double lid) {
    Parameters phi = Frontal();
    phi.eyelid_pitch() = lid;
    phi.gaze_pitch() = lid;
    // The middle of the upper margin, in the model frame (z up).
    return Pose(phi).region[kLeftEye].col(topology::kUpperMargin[3]).z();
  };
  const double rest = upper_lid_height(0), up = upper_lid_height(15), down = upper_lid_height(-15);
  EXPECT_GT(up, rest + 1.0);
  EXPECT_LT(down, rest - 2.0);
  EXPECT_LT(up - rest, rest - down) << "looking down moves the lid more than looking up";
}

TEST(EyeRegionModelTest, LidsNeverCutIntoTheEyeball) {
  for (double pitch : {-30.0, -15.0, 0.0, 15.0, 30.0}) {
    for (double yaw : {-35.0, 0.0, 35.0}) {
      Parameters phi = Frontal();
      phi.gaze_pitch() = pitch;
      phi.gaze_yaw() = yaw;
      phi.eyelid_pitch() = pitch;
      const PosedModel posed = Pose(phi);
      const Eigen::Vector3d gaze_model =
          EyeRegionModel::ModelToHead(kLeftEye).transpose() * EyeRegionModel::GazeInHead(pitch, EyeRegionModel::EyeYaw(phi, kLeftEye));
      for (const auto& loop : topology::kLoops) {
        for (int v : loop) {
          const Eigen::Vector3d p = posed.region[kLeftEye].col(v);
          EXPECT_GE(p.norm(), EyelidRig::EyeballRadius(p.normalized(), gaze_model) + 0.29)
              << "vertex " << v << " at pitch " << pitch << " yaw " << yaw;
        }
      }
    }
  }
}

TEST(EyeRegionModelTest, SkinNormalsFaceTheCameraAndEyeballsAreClosedSpheres) {
  const PosedModel posed = Pose(Frontal());
  // Around the eye opening the skin faces the camera (normal toward -z).
  int toward = 0;
  for (int v : SharedModel()->opening_rim()) toward += posed.parts[kLeftSkin].normals(2, v) < 0;
  EXPECT_EQ(toward, static_cast<int>(SharedModel()->opening_rim().size()));
  const Eigen::Matrix3Xf& ball = posed.parts[kLeftEyeball].positions;
  const Eigen::Vector3f centre = posed.eyes[kLeftEye].centre.cast<float>();
  for (Eigen::Index i = 0; i < ball.cols(); ++i) {
    const float radius = (ball.col(i) - centre).norm();
    EXPECT_GE(radius, 12.0f);
    EXPECT_LE(radius, 13.1f);
  }
}

}  // namespace
}  // namespace gazedirector
