#pragma once

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "gazedirector/redirect/gaze_target.h"

namespace gazedirector {

// A timeline of gaze targets for a video. Each segment starts at a time and
// holds its target (or behaviour) until the next; changes are eased over the
// transition time. JSON:
//   {"transition_s": 0.3,
//    "segments": [{"start_s": 0, "target": "camera"},
//                 {"start_s": 3, "target": {"look_at": [-400, 0, 100]}},
//                 {"start_s": 5, "reading": {"width_deg": 24, "line_s": 1.2, "lines": 4,
//                                             "line_spacing_deg": 3, "pitch_deg": -8}}]}
// Targets are as GazeTarget::FromJson reads them. "reading" sweeps the gaze
// left to right along lines (head frame), with a quick return at each line's
// end, moving down the page.
class GazeScript {
 public:
  static GazeScript Load(const std::filesystem::path& path);
  static GazeScript FromJson(const nlohmann::json& json);
  // A script that holds one target throughout.
  static GazeScript Constant(const GazeTarget& target);

  // The re-posed Φ of a face fitted as `fitted`, at `time_s`.
  Parameters TargetAt(const Parameters& fitted, double time_s) const;
  std::string Describe() const;
  // When each segment starts, in order.
  std::vector<double> StartTimes() const;

 private:
  struct Reading {
    double width_deg = 24, line_s = 1.2, line_spacing_deg = 3, pitch_deg = -8, return_s = 0.12;
    int lines = 4;
  };
  struct Segment {
    double start_s = 0;
    bool reading = false;
    GazeTarget target;
    Reading read;
  };
  // The segment's own target at a time (no easing between segments).
  Parameters SegmentTarget(const Segment& segment, const Parameters& fitted, double time_s) const;

  std::vector<Segment> segments_;
  double transition_s_ = 0.3;
};

}  // namespace gazedirector
