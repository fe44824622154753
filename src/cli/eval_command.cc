// gazedirector eval: accuracy figures on the real data, printed as numbers.
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "cli/common.h"
#include "gazedirector/eval/landmark_accuracy.h"
#include "gazedirector/io/assets.h"
#include "gazedirector/util/error.h"

namespace gazedirector::cli {
namespace {

struct EvalOptions {
  CommonOptions common;
  bool json = false;
  std::string landmarks_xml;
};

int RunLandmarkEval(const EvalOptions& options) {
  ApplyLogLevel(options.common);
  const std::filesystem::path xml = options.landmarks_xml.empty()
                                        ? DefaultDataDir() / "dlib-faces" / "testing_with_face_landmarks.xml"
                                        : std::filesystem::path(options.landmarks_xml);
  if (!std::filesystem::is_regular_file(xml)) Fail(ExitCode::kBadInput, "{}: no such file", xml.string());
  const Assets assets = Assets::Resolve(options.common.assets);
  auto landmark_detector = std::make_shared<LandmarkDetector>(assets.landmark_model());
  FaceTracker tracker(landmark_detector, LoadMeanFace(assets.mean_face()));
  const LandmarkAccuracy accuracy = EvaluateLandmarks(xml, tracker, *landmark_detector);
  const nlohmann::json result = {
      {"faces", accuracy.faces},
      {"detected", accuracy.detected},
      {"mean_error_given_box", accuracy.MeanGivenBox()},
      {"median_error_given_box", accuracy.MedianGivenBox()},
      {"mean_error_pipeline", accuracy.MeanPipeline()},
      {"median_error_pipeline", accuracy.MedianPipeline()},
  };
  if (options.json) {
    fmt::print("{}\n", result.dump());
    return 0;
  }
  fmt::print("landmark error / outer-eye-corner distance on {}\n", xml.string());
  fmt::print("  marked faces               {}\n", accuracy.faces);
  fmt::print("  detected by the pipeline   {} ({:.0f}%)\n", accuracy.detected,
             accuracy.faces ? 100.0 * accuracy.detected / accuracy.faces : 0.0);
  fmt::print("  on the marked box          mean {:.4f}  median {:.4f}\n", accuracy.MeanGivenBox(), accuracy.MedianGivenBox());
  fmt::print("  detection + landmarks      mean {:.4f}  median {:.4f}\n", accuracy.MeanPipeline(), accuracy.MedianPipeline());
  return 0;
}

}  // namespace

Command RegisterEvalCommand(CLI::App& root) {
  auto options = std::make_shared<EvalOptions>();
  CLI::App* app = root.add_subcommand("eval", "Accuracy evaluations on the real data (numbers, not tests)");
  app->require_subcommand(1);
  CLI::App* landmarks = app->add_subcommand("landmarks", "68-point landmark error on hand-marked faces (dlib XML)");
  landmarks->add_option("xml", options->landmarks_xml,
                        "dlib XML with marked faces (default: ../shared/data/dlib-faces/testing_with_face_landmarks.xml)");
  landmarks->add_flag("--json", options->json, "Print one JSON object");
  AddCommonOptions(*landmarks, options->common);
  return {app, [options, landmarks] {
            if (landmarks->parsed()) return RunLandmarkEval(*options);
            return static_cast<int>(ExitCode::kUsage);
          }};
}

}  // namespace gazedirector::cli
