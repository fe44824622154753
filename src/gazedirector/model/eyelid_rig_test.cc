#include "gazedirector/model/eyelid_rig.h"

#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "gazedirector/geometry/rotation.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/model/eye_region_topology.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

using topology::kLoopColumns;
using topology::kLoops;
using topology::kOuterCornerColumn;

// The rig works on the left eye's region in its model frame: the eyeball's
// centre at the origin, -y ahead, z up, +x toward the outer corner.
Eigen::Matrix3Xd MeanRegion() { return testing::SharedModel()->shape_model().mean(); }

// The left eye's gaze in its model frame, as EyeRegionModel::Pose hands it to the rig.
Eigen::Vector3d Looking(double pitch_deg, double yaw_deg = 0) {
  return EyeRegionModel::ModelToHead(kLeftEye).transpose() * EyeRegionModel::GazeInHead(pitch_deg, yaw_deg);
}

Eigen::Matrix3Xd Rigged(double lid_pitch_deg, double closure_deg, const Eigen::Vector3d& gaze) {
  Eigen::Matrix3Xd vertices = MeanRegion();
  EyelidRig().Apply(lid_pitch_deg, closure_deg, gaze, vertices);
  return vertices;
}

TEST(EyelidRigTest, TheEyeballIsTheCorneaAlongTheGazeAndTheScleraElsewhere) {
  for (const Eigen::Vector3d& gaze : {Looking(0), Looking(25, -30)}) {
    // The corneal apex: the cornea's sphere, 8.70 mm about a centre 4.33 mm forward.
    EXPECT_NEAR(EyelidRig::EyeballRadius(gaze, gaze), 13.03, 1e-9);
    EXPECT_DOUBLE_EQ(EyelidRig::EyeballRadius(-gaze, gaze), topology::kScleraRadiusMm);
    // That sphere passes through the limbus ring (5.87 mm about the axis, 10.75 mm forward).
    const double limbus_angle = std::atan2(topology::kLimbusRadiusMm, topology::kLimbusDepthMm);
    const Eigen::Vector3d side = gaze.unitOrthogonal();
    const Eigen::Vector3d at_limbus = std::cos(limbus_angle) * gaze + std::sin(limbus_angle) * side;
    EXPECT_NEAR(EyelidRig::EyeballRadius(at_limbus, gaze), std::hypot(topology::kLimbusRadiusMm, topology::kLimbusDepthMm), 0.01);
    // Away from the gaze the bulge falls smoothly onto the sclera and stays there.
    double previous = EyelidRig::EyeballRadius(gaze, gaze);
    for (int degrees = 1; degrees <= 180; ++degrees) {
      const double angle = DegToRad(degrees);
      const double radius = EyelidRig::EyeballRadius(std::cos(angle) * gaze + std::sin(angle) * side, gaze);
      EXPECT_LE(radius, previous + 1e-12) << degrees << " degrees off the gaze";
      EXPECT_GT(radius, previous - 0.1) << degrees << " degrees off the gaze: no step";
      EXPECT_GE(radius, topology::kScleraRadiusMm);
      if (degrees >= 40) {
        EXPECT_DOUBLE_EQ(radius, topology::kScleraRadiusMm);
      }
      previous = radius;
    }
  }
}

TEST(EyelidRigTest, TheLookDownTextureGrowsAsTheSquareOfLookingDown) {
  EXPECT_EQ(LookDownBlend(20), 0.0);
  EXPECT_EQ(LookDownBlend(0), 0.0);
  EXPECT_DOUBLE_EQ(LookDownBlend(-12.5), 0.25);
  EXPECT_DOUBLE_EQ(LookDownBlend(-25), 1.0);
  EXPECT_DOUBLE_EQ(LookDownBlend(-60), 1.0);
}

// The lids turn about axes through the corners, so the corners stay put
// whatever the lids do, and so does every vertex outside the six loops.
TEST(EyelidRigTest, TheCornersAndTheSkinBeyondTheLoopsStayPut) {
  const Eigen::Matrix3Xd rest = MeanRegion();
  std::vector<bool> in_loop_body(rest.cols(), false);
  for (const auto& loop : kLoops) {
    for (int c = 0; c < kLoopColumns; ++c) in_loop_body[loop[c]] = c != 0 && c != kOuterCornerColumn;
  }
  const struct {
    double lid, closure;
    Eigen::Vector3d gaze;
  } poses[] = {{20, 0, Looking(20)}, {-25, 0, Looking(-25)}, {0, 30, Looking(0)}, {-10, 15, Looking(-10, 35)}};
  for (const auto& pose : poses) {
    const Eigen::Matrix3Xd rigged = Rigged(pose.lid, pose.closure, pose.gaze);
    int moved = 0;
    for (Eigen::Index v = 0; v < rest.cols(); ++v) {
      if (in_loop_body[v]) {
        moved += (rigged.col(v) - rest.col(v)).norm() > 0.05;
      } else {
        EXPECT_EQ(rigged.col(v), rest.col(v)) << "vertex " << v << " at lid " << pose.lid << ", closure " << pose.closure;
      }
    }
    EXPECT_GT(moved, 30) << "lid " << pose.lid << ", closure " << pose.closure;
  }
}

// The rig's promise to the renderer: each loop keeps its own least thickness
// of skin over the eyeball (and the cornea's bulge), however the eye looks.
// In these poses the push binds on the margin loop (0.2 mm less there fails
// 42 checks); the outer loops stand further off than their clearance.
TEST(EyelidRigTest, EachLoopStandsItsClearanceOffTheEyeball) {
  const EyelidRigSettings settings;
  for (double pitch : {-30.0, -10.0, 0.0, 15.0, 30.0}) {
    for (double yaw : {-40.0, 0.0, 40.0}) {
      for (double closure : {0.0, 20.0}) {
        const Eigen::Vector3d gaze = Looking(pitch, yaw);
        const Eigen::Matrix3Xd rigged = Rigged(pitch, closure, gaze);
        for (std::size_t k = 0; k < kLoops.size(); ++k) {
          for (int c = 1; c < kLoopColumns; ++c) {
            if (c == kOuterCornerColumn) continue;
            const Eigen::Vector3d p = rigged.col(kLoops[k][c]);
            EXPECT_GE(p.norm(), EyelidRig::EyeballRadius(p.normalized(), gaze) + settings.clearance_mm[k] - 1e-9)
                << "loop " << k << " column " << c << " at pitch " << pitch << ", yaw " << yaw << ", closure " << closure;
          }
        }
      }
    }
  }
}

// Closing lowers the upper lid and raises the lower one a quarter as far
// (EyelidRigSettings::lower_lid_closure); the outer loops follow less.
TEST(EyelidRigTest, ClosingLowersTheUpperLidAndRaisesTheLowerLess) {
  const Eigen::Matrix3Xd open = Rigged(0, 0, Looking(0));
  const Eigen::Matrix3Xd closed = Rigged(0, 25, Looking(0));
  const int upper_middle = kLoops[0][5], lower_middle = kLoops[0][15];
  const double upper_drop = open(2, upper_middle) - closed(2, upper_middle);
  const double lower_rise = closed(2, lower_middle) - open(2, lower_middle);
  EXPECT_GT(upper_drop, 2.0) << "mm";
  EXPECT_GT(lower_rise, 0.1 * upper_drop);
  EXPECT_LT(lower_rise, 0.5 * upper_drop);
  const double outer_drop = open(2, kLoops[5][5]) - closed(2, kLoops[5][5]);
  EXPECT_GT(outer_drop, 0.0);
  EXPECT_LT(outer_drop, 0.5 * upper_drop) << "the brow side of the lid moves less than its margin";
}

}  // namespace
}  // namespace gazedirector
