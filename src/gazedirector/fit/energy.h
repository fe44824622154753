#pragma once

namespace gazedirector {

// The weights of the paper's energy E = E_img + E_ldmks + E_stats + E_pose.
struct EnergyWeights {
  // T: a pixel's squared RGB error (colours in [0, 1]) counts at most T, the
  // robust ρ(e) = min(√T, e), so that highlights and glasses do not drag the fit.
  double truncation = 0.06;
  // Pixels of the eyeballs count this many times: they carry the gaze, while
  // the skin around them mostly does not.
  double eyeball_pixels = 1.0;
  double landmarks = 2.0;     // λ_ldmks, for the lid points and corners
  double brow_factor = 0.2;   // brows and nose are marked less precisely
  double nose_factor = 0.2;
  double shape = 2e-4;        // λ_geo, per squared standard deviation (of the shape and the pupil's size)
  double texture = 2e-4;      // λ_tex
  double pose = 4e-5;         // λ_pose, per squared degree of eyelid-gaze mismatch
  double closure = 1e-5;      // per squared degree of eyelid closure: open eyes unless the image says otherwise
  double vergence = 2e-5;     // per squared degree of vergence: the eyes' axes meet far away unless the image says otherwise
  // Per squared degree between the gaze and what the crop's appearance reads
  // (AppearanceGaze), where a reading is given (eye patches): λ_app,p for
  // pitch, λ_app,y for yaw.
  double appearance_pitch = 1e-4;
  double appearance_yaw = 3e-6;
  // λ_app,y is multiplied by this where the head reads turned (blended by
  // AppearanceReading::frontal). A turned eye's fit reads only part of its
  // turn in the head, and the reading does better there: with the yaw read
  // in the head's frame (session 48, measured without the frontal yaw), 3
  // gave 3.82 degrees of yaw over all head poses against 4.09 for 1
  // (docs/known-gaps.md). Far stronger pulls also reach frontal heads whose
  // turn reads a few degrees off.
  double appearance_turned_factor = 3.0;

  // Whether an eye patch's fit needs the appearance reading at all.
  bool UsesAppearance() const { return appearance_pitch > 0 || appearance_yaw > 0; }
  // λ for the yaw reading, by how frontal the head reads (1: facing the
  // camera). Squared, so that the turned factor takes over only where the
  // head clearly reads turned.
  double AppearanceYaw(double frontal) const {
    const double turned = (1 - frontal) * (1 - frontal);
    return appearance_yaw * ((1 - turned) + turned * appearance_turned_factor);
  }
};

// The energy's terms for one Φ; image and landmarks are normalised by the
// foreground area as in the paper.
struct EnergyTerms {
  double image = 0;
  double landmarks = 0;
  double stats = 0;
  double pose = 0;  // eyelid-gaze consistency and the vergence prior
  int foreground = 0;  // rendered pixels |P|
  double total() const { return image + landmarks + stats + pose; }
};

}  // namespace gazedirector
