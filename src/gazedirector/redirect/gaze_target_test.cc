#include "gazedirector/redirect/gaze_target.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "gazedirector/fit/face_fit.h"
#include "gazedirector/geometry/rotation.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/model/eyelid_rig.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace {

// A face 60 cm away, a little to the side and turned.
Parameters Face() {
  Parameters phi;
  phi.set_rotation(RotationFromEulerXYZ(Eigen::Vector3d(DegToRad(8), DegToRad(-15), DegToRad(3))));
  phi.block<Block::kTranslation>() = Eigen::Vector3d(40, -20, 600);
  phi.gaze_pitch() = -5, phi.gaze_yaw() = 12, phi.eyelid_pitch() = -4;
  return phi;
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return RadToDeg(std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)));
}

TEST(GazeTargetTest, BothEyesLookAtThePoint) {
  for (const Eigen::Vector3d& point : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(-150, 60, 50), Eigen::Vector3d(80, 30, 300)}) {
    const Parameters phi = Retarget(Face(), point.isZero() ? GazeTarget::Camera() : GazeTarget::Point(point));
    const std::array<EyeGaze, 2> eyes = EyeGazes(phi);
    for (const EyeGaze& eye : eyes) {
      // The shared pitch of the two eyes leaves a small vertical mismatch when
      // the head is rolled; it stays well under a degree.
      EXPECT_LT(AngleDeg(eye.gaze, point - eye.centre), 0.6) << point.transpose();
    }
  }
}

// A point almost straight behind the head, 2 cm to the subject's left: each
// eye's yaw toward it reads near 180 degrees, one eye's +, the other's -.
// Their plain mean (before session 72) sent the eyes straight ahead, away
// from it, without a word; now they turn toward it as far as they can.
TEST(GazeTargetTest, APointBehindTheHeadIsLookedTowardAsFarAsTheEyesTurn) {
  const Parameters face = Face();
  const Eigen::Vector3d behind_left(20, 0, 800);  // head frame: x to the subject's left, z into the head
  const Parameters phi = Retarget(face, GazeTarget::Point(face.rotation() * behind_left + face.translation()));
  EXPECT_DOUBLE_EQ(phi.gaze_yaw(), kMaxRedirectYawDeg);
  EXPECT_NEAR(phi.gaze_pitch(), 0, 1.0);
  EXPECT_TRUE(AtTheEyesReach(phi));
  const Eigen::Vector3d behind_right(-20, 0, 800);
  EXPECT_DOUBLE_EQ(Retarget(face, GazeTarget::Point(face.rotation() * behind_right + face.translation())).gaze_yaw(),
                   -kMaxRedirectYawDeg);
  EXPECT_FALSE(AtTheEyesReach(Retarget(face, GazeTarget::Camera())));
  EXPECT_TRUE(AtTheEyesReach(Retarget(face, GazeTarget::Direction(0, 80, GazeTarget::Frame::kHead))));
}

TEST(GazeTargetTest, OffsetsAddAndTheEyelidsFollow) {
  const Parameters fitted = Face();
  const Parameters moved = Retarget(fitted, GazeTarget::Offset(10, -20));
  EXPECT_DOUBLE_EQ(moved.gaze_pitch(), fitted.gaze_pitch() + 10);
  EXPECT_DOUBLE_EQ(moved.gaze_yaw(), fitted.gaze_yaw() - 20);
  EXPECT_NEAR(moved.eyelid_pitch(), fitted.eyelid_pitch() + EyelidFollow().up * 10, 1e-9);
  EXPECT_NEAR(Retarget(fitted, GazeTarget::Offset(-10, 0)).eyelid_pitch(), fitted.eyelid_pitch() - EyelidFollow().down * 10, 1e-9);
  EXPECT_NEAR(Retarget(fitted, GazeTarget::Offset(10, 0), {1.0, 1.0}).eyelid_pitch(), fitted.eyelid_pitch() + 10, 1e-9);
  EXPECT_EQ(moved.shape(), fitted.shape());
  // Beyond the eye's range the gaze stops at its limit.
  EXPECT_LE(Retarget(fitted, GazeTarget::Offset(0, 90)).gaze_yaw(), 50);
}

// Columbia measures upward changes of up to 10 deg, where the lids follow 0.4
// of them; beyond that the upper lid turns with the iris, one to one, whether
// it starts raised or lowered (the rig turns it by a different share of the
// lid pitch either way).
TEST(GazeTargetTest, BeyondColumbiasRangeTheUpperLidKeepsPaceWithTheIris) {
  const EyelidRigSettings rig;
  const EyelidFollow follow;
  Parameters fitted = Face();
  for (double start : {-20.0, 0.0, 5.0}) {
    fitted.gaze_pitch() = start, fitted.eyelid_pitch() = start;
    const double at_ten = Retarget(fitted, GazeTarget::Offset(10, 0)).eyelid_pitch();
    EXPECT_NEAR(at_ten, start + follow.up * 10, 1e-9) << "from " << start;
    for (double more : {5.0, 15.0}) {
      const double lid = Retarget(fitted, GazeTarget::Offset(10 + more, 0)).eyelid_pitch();
      EXPECT_NEAR(rig.UpperLidTurn(lid) - rig.UpperLidTurn(at_ten), more, 1e-9) << "from " << start << ", " << more << " more";
    }
  }
  // Without it the lids follow 0.4 of the whole change, as Columbia's tuning alone says.
  EyelidFollow measured_only;
  measured_only.keep_pace_beyond = false;
  fitted.gaze_pitch() = 0, fitted.eyelid_pitch() = 0;
  EXPECT_NEAR(Retarget(fitted, GazeTarget::Offset(20, 0), measured_only).eyelid_pitch(), 8, 1e-9);
  EXPECT_NEAR(rig.LidPitchForUpperLidTurn(rig.UpperLidTurn(-7)), -7, 1e-12);
  EXPECT_NEAR(rig.LidPitchForUpperLidTurn(rig.UpperLidTurn(9)), 9, 1e-12);
}

TEST(GazeTargetTest, DirectionsInTheCameraFrameAreSeenByTheCamera) {
  const Parameters phi = Retarget(Face(), GazeTarget::Direction(10, -20, GazeTarget::Frame::kCamera));
  const std::array<EyeGaze, 2> eyes = EyeGazes(phi);
  const Eigen::Vector3d wanted = EyeRegionModel::GazeInHead(10, -20);  // camera axes read like the head's
  EXPECT_LT(AngleDeg(0.5 * (eyes[0].gaze + eyes[1].gaze), wanted), 1.0);
}

TEST(GazeTargetTest, JsonRoundTripAndErrors) {
  for (const GazeTarget& target : {GazeTarget::Camera(), GazeTarget::Point({1, 2, 3}), GazeTarget::Offset(4, 5),
                                   GazeTarget::Direction(6, 7, GazeTarget::Frame::kHead)}) {
    const GazeTarget back = GazeTarget::FromJson(target.ToJson());
    EXPECT_EQ(back.kind, target.kind);
    EXPECT_EQ(back.Describe(), target.Describe());
  }
  EXPECT_THROW(GazeTarget::FromJson(nlohmann::json{{"look_at", {1, 2}}}), Error);
  EXPECT_THROW(GazeTarget::FromJson(nlohmann::json{{"gaze", {1, 2}}, {"frame", "world"}}), Error);
  EXPECT_THROW(GazeTarget::FromJson(nlohmann::json{{"stare", true}}), Error);
}

TEST(GazeTargetTest, RefusesAnglesBeyondAQuarterTurnAndPointsThatAreNotNumbers) {
  EXPECT_NO_THROW(GazeTarget::Direction(90, -90, GazeTarget::Frame::kCamera));
  EXPECT_THROW(GazeTarget::Direction(1000, 0, GazeTarget::Frame::kCamera), Error);
  EXPECT_THROW(GazeTarget::Direction(0, std::nan(""), GazeTarget::Frame::kHead), Error);
  EXPECT_THROW(GazeTarget::Offset(0, -120), Error);
  EXPECT_THROW(GazeTarget::Point({0, std::numeric_limits<double>::infinity(), 500}), Error);
  EXPECT_THROW(GazeTarget::Point({0, 0, 0}), Error);
  EXPECT_THROW(GazeTarget::FromJson(nlohmann::json{{"gaze", {95, 0}}}), Error);
}

}  // namespace
}  // namespace gazedirector
