// gazedirector eval landmarks: 68-point landmark error on hand-marked faces.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/eval_options.h"
#include "gazedirector/eval/landmark_accuracy.h"
#include "gazedirector/face/face_tracker.h"
#include "gazedirector/face/landmark_detector.h"
#include "gazedirector/face/mean_face.h"
#include "gazedirector/io/assets.h"
#include "gazedirector/util/error.h"

namespace gazedirector::cli {

int RunLandmarkEval(const EvalOptions& options) {
  ApplyLogLevel(options.common);
  const std::filesystem::path xml = options.landmarks_xml.empty()
                                        ? DefaultDataDir() / "dlib-faces" / "testing_with_face_landmarks.xml"
                                        : std::filesystem::path(options.landmarks_xml);
  if (!std::filesystem::is_regular_file(xml)) Fail(ExitCode::kBadInput, "{}: no such file", xml.string());
  const Assets assets = Assets::Resolve(options.common.assets);
  auto landmark_detector = LandmarkDetector::Load(assets.landmark_model(), Assets::CacheDir());
  FaceTracker tracker(landmark_detector, LoadMeanFace(assets.mean_face()));
  std::vector<std::pair<double, LandmarkAccuracy>> by_turn;
  for (double turn : options.landmark_turns) by_turn.emplace_back(turn, EvaluateLandmarks(xml, tracker, *landmark_detector, turn));
  auto to_json = [](const LandmarkAccuracy& accuracy) {
    return nlohmann::json{
        {"faces", accuracy.faces},
        {"detected", accuracy.detected},
        {"mean_error_given_box", accuracy.MeanGivenBox()},
        {"median_error_given_box", accuracy.MedianGivenBox()},
        {"mean_error_pipeline", accuracy.MeanPipeline()},
        {"median_error_pipeline", accuracy.MedianPipeline()},
    };
  };
  if (options.json) {
    if (by_turn.size() == 1 && by_turn[0].first == 0) {
      fmt::print("{}\n", to_json(by_turn[0].second).dump());
    } else {
      nlohmann::json turns = nlohmann::json::array();
      for (const auto& [turn, accuracy] : by_turn) {
        nlohmann::json row = to_json(accuracy);
        row["turn_deg"] = turn;
        turns.push_back(row);
      }
      fmt::print("{}\n", nlohmann::json{{"by_turn", turns}}.dump());
    }
    return 0;
  }
  fmt::print("landmark error / outer-eye-corner distance on {}\n", xml.string());
  fmt::print("  {:>8} {:>6} {:>9} {:>22} {:>22}\n", "turn", "faces", "detected", "marked box mean/median",
             "pipeline mean/median");
  for (const auto& [turn, accuracy] : by_turn) {
    const std::string pipeline = accuracy.detected ? fmt::format("{:>13.4f} {:>8.4f}", accuracy.MeanPipeline(), accuracy.MedianPipeline())
                                                   : fmt::format("{:>22}", "none found");
    fmt::print("  {:>7.0f}° {:>6} {:>8.0f}% {:>13.4f} {:>8.4f} {}\n", turn, accuracy.faces,
               accuracy.faces ? 100.0 * accuracy.detected / accuracy.faces : 0.0, accuracy.MeanGivenBox(),
               accuracy.MedianGivenBox(), pipeline);
  }
  fmt::print("  (pipeline: detection + landmarks, over the faces it found; turned photos are turned clockwise as shown)\n");
  return 0;
}

}  // namespace gazedirector::cli
