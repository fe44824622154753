// gazedirector bench: the project's performance figures on the real data.
#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "cli/common.h"
#include "gazedirector/eval/performance.h"
#include "gazedirector/face/face_tracker.h"
#include "gazedirector/io/assets.h"
#include "gazedirector/io/json_format.h"
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

  auto landmark_detector = LandmarkDetector::Load(assets.landmark_model(), Assets::CacheDir());
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
  // Each figure: a name, its target (the issues'), and a measurement,
  // repeated; the median is reported, with the runs' range: these VMs'
  // speed varies by a third or more from minute to minute.
  struct Figure {
    std::string name;
    double target;
    std::function<double()> measure;
  };
  const std::vector<Figure> figures = {
      {"landmarks_fps", 30, [&] {
         FaceTracker tracker(landmark_detector, mean_face);
         return MeasureLandmarksFps(d3, tracker);
       }},
      {"renders_per_s", 5000, [&] { return MeasureRendersPerSecond(model(), 2, 3.0); }},
      {"fit_fps", 12, [&] { return MeasureFitFps(model(), clip()); }},
      {"track_fps", 12, [&] { return MeasureTrackFps(model(), landmark_detector, mean_face, d3, 150); }},
      {"redirect_fps", 80, [&] { return MeasureRedirectFps(model(), clip()); }},
  };
  for (const std::string& name : options.only) {
    if (std::none_of(figures.begin(), figures.end(), [&](const Figure& figure) { return figure.name == name; })) {
      std::vector<std::string> names;
      for (const Figure& figure : figures) names.push_back(figure.name);
      Fail(ExitCode::kUsage, "bench --only: unknown figure '{}' (one of {})", name, fmt::join(names, ", "));
    }
  }
  nlohmann::json results = nlohmann::json::object();
  if (!options.json) fmt::print("{:<20} {:>10}  {:>19}  {:>8}\n", "figure", "median", "runs (min-max)", "target");
  for (const Figure& figure : figures) {
    if (!options.only.empty() && std::find(options.only.begin(), options.only.end(), figure.name) == options.only.end()) {
      continue;
    }
    std::vector<double> runs;
    for (int i = 0; i < options.repeats; ++i) runs.push_back(figure.measure());
    const double median = Median(runs);
    const auto [low, high] = std::minmax_element(runs.begin(), runs.end());
    results[figure.name] = RoundTo(median, 1);
    for (double run : runs) results["runs"][figure.name].push_back(RoundTo(run, 1));
    if (!options.json) {
      fmt::print("{:<20} {:>10.1f}  {:>19}  {:>8}{}\n", figure.name, median, fmt::format("{:.1f}-{:.1f}", *low, *high),
                 fmt::format(">= {:g}", figure.target), *low < figure.target ? "  (a run below the target)" : "");
    }
  }
  if (options.json) fmt::print("{}\n", results.dump());
  return 0;
}

}  // namespace

Command RegisterBenchCommand(CLI::App& root) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* app = root.add_subcommand("bench", "Measure the project's performance figures on the real data in ../shared "
                                               "(medians of repeated runs)");
  app->add_flag("--json", options->json, "Print one JSON object: each figure's median by name, and under \"runs\" its single runs");
  app->add_option("--data", options->data, "The shared data folder (default: ../shared/data beside the repository)");
  app->add_option("--repeats", options->repeats, "Runs per figure; the median is reported")->check(CLI::Range(1, 100));
  app->add_option("--only", options->only, "Measure only these figures");
  AddCommonOptions(*app, options->common);
  return {app, [options] { return RunBench(*options); }};
}

}  // namespace gazedirector::cli
