#include "gazedirector/fit/fit_options.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "gazedirector/util/error.h"

namespace gazedirector {
namespace {

using Accessor = std::function<double&(FitOptions&)>;

const std::map<std::string, Accessor>& Options() {
  static const std::map<std::string, Accessor> options = {
      {"truncation", [](FitOptions& o) -> double& { return o.weights.truncation; }},
      {"eyeball_pixels", [](FitOptions& o) -> double& { return o.weights.eyeball_pixels; }},
      {"landmarks", [](FitOptions& o) -> double& { return o.weights.landmarks; }},
      {"brow_factor", [](FitOptions& o) -> double& { return o.weights.brow_factor; }},
      {"nose_factor", [](FitOptions& o) -> double& { return o.weights.nose_factor; }},
      {"shape_prior", [](FitOptions& o) -> double& { return o.weights.shape; }},
      {"texture_prior", [](FitOptions& o) -> double& { return o.weights.texture; }},
      {"pose_prior", [](FitOptions& o) -> double& { return o.weights.pose; }},
      {"vergence_prior", [](FitOptions& o) -> double& { return o.weights.vergence; }},
      {"closure_prior", [](FitOptions& o) -> double& { return o.weights.closure; }},
      {"appearance_pitch", [](FitOptions& o) -> double& { return o.weights.appearance_pitch; }},
      {"appearance_yaw", [](FitOptions& o) -> double& { return o.weights.appearance_yaw; }},
      {"appearance_turned_factor", [](FitOptions& o) -> double& { return o.weights.appearance_turned_factor; }},
      {"tolerance", [](FitOptions& o) -> double& { return o.tolerance; }},
      {"first_step", [](FitOptions& o) -> double& { return o.first_step; }},
      {"step_growth", [](FitOptions& o) -> double& { return o.step_growth; }},
      {"landmark_final", [](FitOptions& o) -> double& { return o.landmark_final; }},
      {"jump_search_step", [](FitOptions& o) -> double& { return o.jump_search_step; }},
  };
  return options;
}

double ParseNumber(const std::string& text, const std::string& assignment) {
  try {
    std::size_t used = 0;
    const double value = std::stod(text, &used);
    if (used != text.size()) throw std::invalid_argument("trailing characters");
    if (!std::isfinite(value)) throw std::invalid_argument("not finite");
    return value;
  } catch (const std::exception&) {
    Fail(ExitCode::kUsage, "fit option '{}': the value is not a finite number", assignment);
  }
}

// Holds every parameter of `block` at its start (or frees them all).
void HoldBlock(FitOptions& options, Block block, bool held) {
  if (held) {
    Hold(options.free, {block});
    return;
  }
  const ParameterMask block_mask = MaskOf({block});
  for (int i = 0; i < kNumParameters; ++i) options.free[i] = options.free[i] || block_mask[i];
}

bool BlockHeld(const FitOptions& options, Block block) {
  const ParameterMask block_mask = MaskOf({block});
  for (int i = 0; i < kNumParameters; ++i) {
    if (block_mask[i] && options.free[i]) return false;
  }
  return true;
}

}  // namespace

void SetFitOption(FitOptions& options, const std::string& assignment) {
  const auto equals = assignment.find('=');
  if (equals == std::string::npos) Fail(ExitCode::kUsage, "fit option '{}': expected name=value", assignment);
  const std::string name = assignment.substr(0, equals);
  const std::string text = assignment.substr(equals + 1);
  if (name == "pitch_starts") {  // a fresh fit's starting pitches, degrees, comma-separated
    std::vector<double> starts;
    for (std::size_t begin = 0; begin <= text.size();) {
      const std::size_t comma = std::min(text.find(',', begin), text.size());
      const double start = ParseNumber(text.substr(begin, comma - begin), assignment);
      if (std::abs(start) > kGazePitchBoundDeg) {
        Fail(ExitCode::kUsage, "fit option pitch_starts: each start must be within ±{} degrees", kGazePitchBoundDeg);
      }
      starts.push_back(start);
      begin = comma + 1;
    }
    options.pitch_starts = starts;
    return;
  }
  const double value = ParseNumber(text, assignment);
  if (name == "iterations") {
    if (value < 1 || value > 1000) Fail(ExitCode::kUsage, "fit option iterations must be 1..1000");
    options.max_iterations = static_cast<int>(value);
    return;
  }
  if (name == "work_width") {
    if (value < 32 || value > 2000) Fail(ExitCode::kUsage, "fit option work_width must be 32..2000");
    options.work_width = static_cast<int>(value);
    return;
  }
  if (name == "hold_rotation") {  // keep the eye region's rotation at its start
    HoldBlock(options, Block::kRotation, value != 0);
    return;
  }
  if (name == "hold_shape") {  // keep the shape PCA at its start (the mean)
    HoldBlock(options, Block::kShape, value != 0);
    return;
  }
  if (name == "gaze_search") {
    options.gaze_search = value != 0;
    return;
  }
  if (name == "coarse_to_fine") {
    options.coarse_to_fine = value != 0;
    return;
  }
  const auto found = Options().find(name);
  if (found == Options().end()) Fail(ExitCode::kUsage, "unknown fit option '{}' (see --help)", name);
  if (value < 0) Fail(ExitCode::kUsage, "fit option {} must not be negative", name);
  found->second(options) = value;
}

FitOptions EyePatchFitOptions(const std::vector<std::string>& assignments) {
  FitOptions options;
  options.work_width = kEyePatchWorkWidth;
  // The crop's framing (the mean of the eye's landmarks at the centre) places
  // the start but does not pull the fit: the landmarks the crops were cut
  // around move with the iris, and pulled to them a turned eye's fit read
  // 0.72 of its turn in the head instead of 0.87 (docs/known-gaps.md, session 41).
  options.weights.landmarks = 0;
  for (const std::string& assignment : assignments) SetFitOption(options, assignment);
  return options;
}

std::vector<std::string> ListFitOptions() {
  std::vector<std::string> names = {"iterations", "work_width", "coarse_to_fine", "hold_rotation", "hold_shape", "gaze_search",
                                    "pitch_starts"};
  for (const auto& [name, accessor] : Options()) names.push_back(name);
  return names;
}

nlohmann::json FitOptionsToJson(const FitOptions& options) {
  nlohmann::json json = {{"iterations", options.max_iterations},
                         {"work_width", options.work_width},
                         {"coarse_to_fine", options.coarse_to_fine},
                         {"hold_rotation", BlockHeld(options, Block::kRotation)},
                         {"hold_shape", BlockHeld(options, Block::kShape)},
                         {"gaze_search", options.gaze_search},
                         {"pitch_starts", options.pitch_starts}};
  FitOptions copy = options;
  for (const auto& [name, accessor] : Options()) json[name] = accessor(copy);
  return json;
}

}  // namespace gazedirector
