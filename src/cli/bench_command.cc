// gazedirector bench: the project's performance figures on the real data.
#include <functional>
#include <map>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "cli/common.h"
#include "gazedirector/eval/performance.h"
#include "gazedirector/face/face_tracker.h"
#include "gazedirector/io/assets.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/statistics.h"

namespace gazedirector::cli {
namespace {

struct BenchOptions {
  CommonOptions common;
  std::string data;
  bool json = false;
  int repeats = 3;
  std::vector<std::string> only;
};

int RunBench(const BenchOptions& options) {
  ApplyLogLevel(options.common);
  if (options.json) spdlog::set_level(spdlog::level::warn);
  const Assets assets = Assets::Resolve(options.common.assets);
  const std::filesystem::path data = options.data.empty() ? DefaultDataDir() : std::filesystem::path(options.data);
  const std::filesystem::path d3 = data / "video" / "d3.mp4";

  auto landmark_detector = std::make_shared<LandmarkDetector>(assets.landmark_model());
  const MeanFace mean_face = LoadMeanFace(assets.mean_face());

  std::shared_ptr<const EyeRegionModel> loaded_model;
  auto model = [&] {
    if (!loaded_model) loaded_model = EyeRegionModel::Load(assets);
    return loaded_model;
  };
  // 90 frames of d3.mp4 with their landmarks, decoded and tracked once (not timed).
  std::optional<TrackedClip> loaded_clip;
  auto clip = [&]() -> const TrackedClip& {
    if (!loaded_clip) {
      FaceTracker tracker(landmark_detector, mean_face);
      loaded_clip = LoadTrackedClip(d3, tracker, 90);
    }
    return *loaded_clip;
  };
  // Each figure: a name and a measurement, repeated; the median is reported.
  std::vector<std::pair<std::string, std::function<double()>>> figures = {
      {"landmarks_fps", [&] {
         FaceTracker tracker(landmark_detector, mean_face);
         return MeasureLandmarksFps(d3, tracker);
       }},
      {"renders_per_s", [&] { return MeasureRendersPerSecond(model(), 2, 3.0); }},
      {"fit_fps", [&] { return MeasureFitFps(model(), clip()); }},
      {"track_fps", [&] { return MeasureTrackFps(model(), landmark_detector, mean_face, d3, 150); }},
      {"redirect_fps", [&] { return MeasureRedirectFps(model(), clip()); }},
  };
  nlohmann::json results = nlohmann::json::object();
  for (const auto& [name, measure] : figures) {
    if (!options.only.empty() && std::find(options.only.begin(), options.only.end(), name) == options.only.end()) continue;
    std::vector<double> runs;
    for (int i = 0; i < options.repeats; ++i) runs.push_back(measure());
    const double median = Median(runs);
    results[name] = std::round(median * 10) / 10;
    spdlog::debug("{}: runs {}", name, nlohmann::json(runs).dump());
    if (!options.json) fmt::print("{:<20} {:>10.1f}\n", name, median);
  }
  if (options.json) fmt::print("{}\n", results.dump());
  return 0;
}

}  // namespace

Command RegisterBenchCommand(CLI::App& root) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* app = root.add_subcommand("bench", "Measure the project's performance figures on the real data in ../shared "
                                               "(medians of repeated runs)");
  app->add_flag("--json", options->json, "Print one JSON object of the named figures");
  app->add_option("--data", options->data, "The shared data folder (default: ../shared/data beside the repository)");
  app->add_option("--repeats", options->repeats, "Runs per figure; the median is reported")->check(CLI::Range(1, 100));
  app->add_option("--only", options->only, "Measure only these figures");
  AddCommonOptions(*app, options->common);
  return {app, [options] { return RunBench(*options); }};
}

}  // namespace gazedirector::cli
