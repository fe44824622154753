#include "gazedirector/model/eyelid_rig.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "gazedirector/geometry/rotation.h"
#include "gazedirector/model/eye_region_topology.h"

namespace gazedirector {
namespace {

// The cornea as a sphere through the limbus ring (5.87 mm radius, 10.75 mm
// forward) and the corneal apex (13.03 mm forward).
constexpr double kCorneaCentreMm = 4.33;
constexpr double kCorneaRadiusMm = 8.70;
constexpr double kLookDownFullDeg = 25.0;

// How far each loop column lies from the corner axis, as a fraction of the
// lid's middle: sin(pi * along) with along 0 at the inner corner and 1 at the
// outer one, along the upper lid (columns 1-9) and back along the lower.
const std::array<double, topology::kLoopColumns>& MidLid() {
  static const std::array<double, topology::kLoopColumns> table = [] {
    std::array<double, topology::kLoopColumns> mid_lid{};
    for (int c = 0; c < topology::kLoopColumns; ++c) {
      const bool upper = c < topology::kOuterCornerColumn;
      const double along = upper ? c / 10.0 : (topology::kLoopColumns - c) / 10.0;
      mid_lid[c] = std::sin(kPi * along);
    }
    return mid_lid;
  }();
  return table;
}

}  // namespace


double EyelidRig::EyeballRadius(const Eigen::Vector3d& u, const Eigen::Vector3d& gaze) {
  const double cosine = u.dot(gaze);
  double radius = topology::kScleraRadiusMm;
  if (cosine > 0) {
    const double sine_squared = 1.0 - cosine * cosine;
    const double disc = kCorneaRadiusMm * kCorneaRadiusMm - kCorneaCentreMm * kCorneaCentreMm * sine_squared;
    if (disc > 0) radius = std::max(radius, kCorneaCentreMm * cosine + std::sqrt(disc));
  }
  return radius;
}

double LookDownBlend(double lid_pitch_deg) {
  const double down = std::clamp(-lid_pitch_deg / kLookDownFullDeg, 0.0, 1.0);
  return down * down;
}

void EyelidRig::Apply(double lid_pitch_deg, double closure_deg, const Eigen::Vector3d& gaze,
                      Eigen::Matrix3Xd& vertices) const {
  using topology::kLoopColumns;
  using topology::kLoops;
  const double lid_angle = DegToRad(settings_.UpperLidTurn(lid_pitch_deg));
  const double closure = DegToRad(closure_deg);
  const Eigen::Vector3d inner = vertices.col(topology::kRigInnerCorner);

  std::array<std::array<Eigen::Vector3d, kLoopColumns>, kLoops.size()> offset;
  const bool moves = lid_angle != 0.0 || closure != 0.0;
  const std::array<double, kLoopColumns>& mid_lids = MidLid();
  for (std::size_t k = 0; k < kLoops.size(); ++k) {
    offset[k].fill(Eigen::Vector3d::Zero());
    if (!moves) continue;
    const Eigen::Vector3d outer = vertices.col(kLoops[k][topology::kOuterCornerColumn]);
    const Eigen::Vector3d axis = (outer - inner).normalized();
    const double upper_angle = settings_.loop_strength[k] * (lid_angle - closure);
    const double lower_angle =
        settings_.loop_strength[k] * (settings_.lower_lid_ratio * lid_angle + settings_.lower_lid_closure * closure);
    // The axis runs toward +x (the outer corner); a negative turn about it lifts the front of the lid.
    const Eigen::Matrix3d upper_turn = Eigen::AngleAxisd(-upper_angle, axis).toRotationMatrix();
    const Eigen::Matrix3d lower_turn = Eigen::AngleAxisd(-lower_angle, axis).toRotationMatrix();
    for (int c = 1; c < kLoopColumns; ++c) {  // the corners (columns 0 and the outer one) stay
      if (c == topology::kOuterCornerColumn) continue;
      const bool upper = c < topology::kOuterCornerColumn;
      const double mid_lid = mid_lids[c];
      const Eigen::Vector3d v = vertices.col(kLoops[k][c]);
      // The pivot slides from the corner axis toward the eyeball centre mid-lid.
      const Eigen::Vector3d on_axis = inner + (v - inner).dot(axis) * axis;
      const Eigen::Vector3d centre_in_plane = on_axis.dot(axis) * axis;
      const Eigen::Vector3d pivot = (1.0 - mid_lid) * on_axis + mid_lid * centre_in_plane;
      const Eigen::Vector3d moved = pivot + (upper ? upper_turn : lower_turn) * (v - pivot);
      offset[k][c] = moved - v;
    }
  }
  // The outer loops are relaxed toward the inner loop's offset, so the skin stretches smoothly.
  for (std::size_t k = 4; k < kLoops.size(); ++k) {
    const double ratio = settings_.loop_strength[k] / settings_.loop_strength[k - 1];
    for (int c = 0; c < kLoopColumns; ++c) offset[k][c] = 0.5 * offset[k][c] + 0.5 * ratio * offset[k - 1][c];
  }
  for (std::size_t k = 0; k < kLoops.size(); ++k) {
    for (int c = 0; c < kLoopColumns; ++c) vertices.col(kLoops[k][c]) += offset[k][c];
  }

  // Shrink-wrap: push each lid vertex out to its least thickness over the
  // eyeball, and pass the push on to the loops outside it.
  for (int c = 1; c < kLoopColumns; ++c) {
    if (c == topology::kOuterCornerColumn) continue;
    double push = 0;
    for (std::size_t k = 0; k < kLoops.size(); ++k) {
      auto v = vertices.col(kLoops[k][c]);
      const double distance = v.norm();
      const Eigen::Vector3d u = v / distance;
      const double needed = EyeballRadius(u, gaze) + settings_.clearance_mm[k];
      push = std::max(push * settings_.loop_strength[k], needed - distance);
      if (push > 0) v += push * u;
    }
  }
}

}  // namespace gazedirector
