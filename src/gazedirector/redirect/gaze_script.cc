#include "gazedirector/redirect/gaze_script.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <type_traits>

#include <fmt/format.h>

#include "gazedirector/io/json_format.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace {

// `object[key]` as a number, `fallback` where it is missing.
template <typename Number>
Number NumberOr(const nlohmann::json& object, const char* key, Number fallback) {
  const auto entry = object.find(key);
  if (entry == object.end()) return fallback;
  if (!entry->is_number()) Fail(ExitCode::kBadInput, "\"{}\" must be a number, not {}", key, entry->dump());
  const double value = entry->get<double>();
  if constexpr (std::is_integral_v<Number>) {
    if (value != std::floor(value)) Fail(ExitCode::kBadInput, "\"{}\" must be a whole number, not {}", key, entry->dump());
    if (std::abs(value) > std::numeric_limits<Number>::max()) {
      Fail(ExitCode::kBadInput, "\"{}\" is out of range: {}", key, entry->dump());
    }
  }
  return static_cast<Number>(value);
}

double Smoothstep(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

}  // namespace

GazeScript GazeScript::Load(const std::filesystem::path& path) {
  std::ifstream stream(path);
  if (!stream) Fail(ExitCode::kBadInput, "{}: cannot read the gaze script", path.string());
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(stream);
  } catch (const nlohmann::json::exception& e) {
    Fail(ExitCode::kBadInput, "{}: invalid JSON ({})", path.string(), JsonErrorText(e));
  }
  try {
    return FromJson(json);
  } catch (const nlohmann::json::exception& e) {
    Fail(ExitCode::kBadInput, "{}: {}", path.string(), JsonErrorText(e));
  } catch (const Error& e) {
    Fail(ExitCode::kBadInput, "{}: {}", path.string(), e.what());
  }
}

GazeScript GazeScript::FromJson(const nlohmann::json& json) {
  GazeScript script;
  if (!json.is_object()) Fail(ExitCode::kBadInput, "a gaze script is a JSON object with a \"segments\" list");
  script.transition_s_ = NumberOr(json, "transition_s", 0.3);
  if (!(script.transition_s_ >= 0)) Fail(ExitCode::kBadInput, "transition_s must be 0 or more");
  if (!json.contains("segments") || !json["segments"].is_array() || json["segments"].empty()) {
    Fail(ExitCode::kBadInput, "a gaze script needs a non-empty \"segments\" list");
  }
  double last = -1e9;
  for (const nlohmann::json& entry : json["segments"]) {
    if (!entry.is_object()) Fail(ExitCode::kBadInput, "each segment is a JSON object, not {}", entry.dump());
    Segment segment;
    segment.start_s = NumberOr(entry, "start_s", 0.0);
    if (segment.start_s < last) Fail(ExitCode::kBadInput, "segments must be in order of start_s");
    last = segment.start_s;
    if (entry.contains("reading")) {
      const nlohmann::json& r = entry["reading"];
      if (!r.is_object()) Fail(ExitCode::kBadInput, "reading: a JSON object, not {}", r.dump());
      segment.reading = true;
      segment.read.width_deg = NumberOr(r, "width_deg", segment.read.width_deg);
      segment.read.line_s = NumberOr(r, "line_s", segment.read.line_s);
      segment.read.lines = NumberOr(r, "lines", segment.read.lines);
      segment.read.line_spacing_deg = NumberOr(r, "line_spacing_deg", segment.read.line_spacing_deg);
      segment.read.pitch_deg = NumberOr(r, "pitch_deg", segment.read.pitch_deg);
      if (!(segment.read.line_s > 0.2) || segment.read.lines < 1) {
        Fail(ExitCode::kBadInput, "reading: line_s must exceed 0.2 s and lines be at least 1");
      }
      // The sweep's first and last gaze, so that a bad angle fails here and not in the middle of a video.
      const double last_pitch = segment.read.pitch_deg - segment.read.line_spacing_deg * (segment.read.lines - 1);
      GazeTarget::Direction(segment.read.pitch_deg, 0.5 * segment.read.width_deg, GazeTarget::Frame::kHead);
      GazeTarget::Direction(last_pitch, -0.5 * segment.read.width_deg, GazeTarget::Frame::kHead);
    } else if (entry.contains("target")) {
      segment.target = GazeTarget::FromJson(entry["target"]);
    } else {
      Fail(ExitCode::kBadInput, "each segment needs a \"target\" or \"reading\"");
    }
    script.segments_.push_back(segment);
  }
  return script;
}

GazeScript GazeScript::Constant(const GazeTarget& target) {
  GazeScript script;
  Segment segment;
  segment.target = target;
  script.segments_.push_back(segment);
  return script;
}

Parameters GazeScript::SegmentTarget(const Segment& segment, const Parameters& fitted, double time_s) const {
  if (!segment.reading) return Retarget(fitted, segment.target);
  const Reading& r = segment.read;
  const double local = std::max(0.0, time_s - segment.start_s);
  const double period = r.line_s + r.return_s;
  const int line = std::min(r.lines - 1, static_cast<int>(local / period));
  const double in_line = local - line * period;
  // Left to right (image left to right: toward the subject's right), then a quick return.
  const double progress = in_line < r.line_s ? in_line / r.line_s : 1.0 - Smoothstep((in_line - r.line_s) / r.return_s);
  const bool finished = local >= r.lines * period;
  const double yaw = finished ? -0.5 * r.width_deg : 0.5 * r.width_deg - r.width_deg * progress;
  const double pitch = r.pitch_deg - r.line_spacing_deg * line;
  return Retarget(fitted, GazeTarget::Direction(pitch, yaw, GazeTarget::Frame::kHead));
}

Parameters GazeScript::TargetAt(const Parameters& fitted, double time_s) const {
  std::size_t index = 0;
  while (index + 1 < segments_.size() && segments_[index + 1].start_s <= time_s) ++index;
  const Parameters current = SegmentTarget(segments_[index], fitted, time_s);
  if (index == 0 || transition_s_ <= 0) return current;
  const double since = time_s - segments_[index].start_s;
  if (since >= transition_s_) return current;
  const Parameters previous = SegmentTarget(segments_[index - 1], fitted, segments_[index].start_s);
  return BlendGaze(previous, current, Smoothstep(since / transition_s_));
}

std::vector<double> GazeScript::StartTimes() const {
  std::vector<double> starts;
  for (const Segment& segment : segments_) starts.push_back(segment.start_s);
  return starts;
}

std::string GazeScript::Describe() const {
  if (segments_.size() == 1 && !segments_[0].reading) return segments_[0].target.Describe();
  return fmt::format("a script of {} segments", segments_.size());
}

}  // namespace gazedirector
