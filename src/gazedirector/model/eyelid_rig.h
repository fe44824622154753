#pragma once

#include <array>

#include <Eigen/Core>

namespace gazedirector {

// How strongly the lids follow the eyelid pitch; tuned on real eyes.
struct EyelidRigSettings {
  double up_gain = 0.6;     // looking up lifts the upper lid by this fraction of the pitch
  double down_gain = 1.0;   // looking down lowers it by this fraction (the "downness" of the source rig)
  double lower_lid_ratio = 1.0 / 3.0;  // the lower lid moves a third as much
  double lower_lid_closure = 0.25;     // closing raises the lower lid by this fraction of the closure
  std::array<double, 6> loop_strength = {1.0, 1.0, 1.0, 0.8, 0.4, 0.2};
  // Least skin thickness over the eyeball per loop (mm), kept by shrink-wrapping.
  std::array<double, 6> clearance_mm = {0.3, 0.6, 1.0, 1.5, 2.0, 2.5};

  // How far the upper lid turns (degrees, up positive) at `lid_pitch_deg`, and back.
  double UpperLidTurn(double lid_pitch_deg) const { return lid_pitch_deg * (lid_pitch_deg > 0 ? up_gain : down_gain); }
  double LidPitchForUpperLidTurn(double turn_deg) const { return turn_deg / (turn_deg > 0 ? up_gain : down_gain); }
};

// The procedural lid rig: the edge loops around the eye rotate about axes
// through the eye corners by an angle proportional to the eyelid pitch (the
// pivot sliding toward the eyeball centre mid-lid, so the lid slides over the
// eyeball like a shell), then the lids are pushed out wherever the eyeball or
// its corneal bulge would cut through them.
class EyelidRig {
 public:
  explicit EyelidRig(EyelidRigSettings settings = {}) : settings_(settings) {}

  // Poses the lids of `vertices` (the facial mesh of the left eye in the model
  // frame, mm, eyeball centre at the origin) for `lid_pitch_deg`, closed by
  // `closure_deg` (the upper lid lowered by that angle, the lower raised a
  // little), with the eyeball looking along the unit vector `gaze` (model
  // frame; (0,-1,0) ahead).
  void Apply(double lid_pitch_deg, double closure_deg, const Eigen::Vector3d& gaze, Eigen::Matrix3Xd& vertices) const;

  // The eyeball's outer surface radius along unit direction `u` when it looks
  // along `gaze`: the sclera sphere, or the corneal bulge in front.
  static double EyeballRadius(const Eigen::Vector3d& u, const Eigen::Vector3d& gaze);

  const EyelidRigSettings& settings() const { return settings_; }

 private:
  EyelidRigSettings settings_;
};

// How much of the look-down skin texture shows: the square of how far down
// the lids are, reaching 1 at 25 degrees down.
double LookDownBlend(double lid_pitch_deg);

}  // namespace gazedirector
