#include "gazedirector/model/parameters.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "gazedirector/util/error.h"

namespace gazedirector {
namespace {

TEST(ParametersTest, BlocksTileTheVectorWithoutGaps) {
  int next = 0;
  for (const BlockLayout& layout : kBlockLayout) {
    EXPECT_EQ(layout.offset, next) << layout.name;
    next += layout.size;
  }
  EXPECT_EQ(next, kNumParameters);
  EXPECT_EQ(Parameters::NameOf(LayoutOf(Block::kGaze).offset + 1), "gaze_pitch_yaw_vergence_deg[1]");
  EXPECT_EQ(Parameters::BlockOf(LayoutOf(Block::kEyelid).offset), Block::kEyelid);
}

TEST(ParametersTest, JsonRoundTripsAndRejectsUnknownOrMisshapenBlocks) {
  Parameters phi;
  phi.gaze_pitch() = -7.5;
  phi.gaze_yaw() = 12.0;
  phi.shape()[3] = 0.8;
  phi.set_rotation(Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix());
  const Parameters back = Parameters::FromJson(phi.ToJson());
  EXPECT_LT((back.values - phi.values).norm(), 1e-12);
  EXPECT_LT((back.rotation() - phi.rotation()).norm(), 1e-12);

  nlohmann::json json = phi.ToJson();
  json["gaze_pitch_yaw_vergence_deg"] = {1, 2};
  EXPECT_THROW(Parameters::FromJson(json), Error);
  json = phi.ToJson();
  json["gaze"] = 3;
  EXPECT_THROW(Parameters::FromJson(json), Error);
  json = phi.ToJson();
  json["gaze_pitch_yaw_vergence_deg"] = {1, 500, 0};
  EXPECT_THROW(Parameters::FromJson(json), Error);
  json = phi.ToJson();
  json["translation_mm"] = {0, 0, -100};
  EXPECT_THROW(Parameters::FromJson(json), Error);
  json = phi.ToJson();
  json["pupil_size"] = 1.2;  // a pupil wider than its iris
  EXPECT_THROW(Parameters::FromJson(json), Error);
  // Missing blocks keep their defaults (fits written before the pupil was
  // fitted have the texture's pupil).
  const Parameters partial = Parameters::FromJson(nlohmann::json{{"eyelid_pitch_deg", 5.0}});
  EXPECT_EQ(partial.eyelid_pitch(), 5.0);
  EXPECT_EQ(partial.interocular(), Parameters().interocular());
  EXPECT_EQ(partial.pupil_size(), 0.49);
}

TEST(ParametersTest, HoldingBlocksLeavesTheOthersAsTheyWere) {
  ParameterMask free = AllParameters();
  free[LayoutOf(Block::kRotation).offset] = false;
  Hold(free, {Block::kShape, Block::kGaze});
  const ParameterMask held = MaskOf({Block::kShape, Block::kGaze});
  for (int i = 0; i < kNumParameters; ++i) {
    EXPECT_EQ(free[i], !held[i] && i != LayoutOf(Block::kRotation).offset) << i;
  }
}

TEST(ParametersTest, LightDirectionFollowsItsAngles) {
  Parameters phi;
  phi.block<Block::kLightDirection>() = Eigen::Vector2d(0, 0);
  EXPECT_LT((phi.LightDirection() - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12) << "from the camera";
  phi.block<Block::kLightDirection>() = Eigen::Vector2d(90, 0);
  EXPECT_LT((phi.LightDirection() - Eigen::Vector3d(0, -1, 0)).norm(), 1e-12) << "from above";
}

TEST(ParametersTest, LightDirectionJacobianMatchesCentralDifferences) {
  for (const Eigen::Vector2d& angles : {Eigen::Vector2d(25, -15), Eigen::Vector2d(-60, 70), Eigen::Vector2d(0, 0)}) {
    Parameters phi;
    phi.block<Block::kLightDirection>() = angles;
    const Eigen::Matrix<double, 3, 2> jacobian = phi.LightDirectionJacobian();
    for (int k = 0; k < 2; ++k) {
      constexpr double kStepDeg = 1e-4;
      Parameters up = phi, down = phi;
      up.block<Block::kLightDirection>()[k] += kStepDeg;
      down.block<Block::kLightDirection>()[k] -= kStepDeg;
      const Eigen::Vector3d numerical = (up.LightDirection() - down.LightDirection()) / (2 * kStepDeg);
      EXPECT_LT((jacobian.col(k) - numerical).norm(), 1e-9) << "angles " << angles.transpose() << ", column " << k;
      EXPECT_GT(jacobian.col(k).norm(), 1e-3) << "a degree of either angle moves the light";
    }
  }
}

}  // namespace
}  // namespace gazedirector
