// gazedirector eval redirect-columbia: redirection error on the Columbia crops.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/eval_options.h"
#include "gazedirector/io/image_io.h"
#include "gazedirector/io/json_format.h"
#include "gazedirector/io/text_writer.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/progress.h"
#include "gazedirector/util/statistics.h"
#include "gazedirector/util/timer.h"
#include "gazedirector/viz/plot.h"

namespace gazedirector::cli {
namespace {

// The cumulative distribution of per-crop errors for each condition, as the paper's figure.
cv::Mat ErrorCdfPlot(const std::vector<RedirectColumbiaCase>& cases) {
  LinePlot plot("Gaze redirection error on Columbia crops", "mean absolute pixel error (8-bit levels)",
                "fraction of crops");
  auto add = [&](const std::string& name, auto member, cv::Scalar colour) {
    std::vector<double> errors;
    for (const RedirectColumbiaCase& c : cases) errors.push_back(c.*member);
    std::sort(errors.begin(), errors.end());
    std::vector<double> fraction;
    for (std::size_t i = 0; i < errors.size(); ++i) fraction.push_back((i + 1.0) / errors.size());
    plot.AddSeries(name, errors, fraction, colour);
  };
  add("(a) no redirection", &RedirectColumbiaCase::error_none, cv::Scalar(120, 120, 120));
  add("(b) eyeballs only", &RedirectColumbiaCase::error_eyeballs, cv::Scalar(200, 120, 30));
  add("(c) eyeballs and eyelids", &RedirectColumbiaCase::error_full, cv::Scalar(40, 40, 210));
  plot.SetYRange(0, 1);
  return plot.Draw();
}

// The three conditions' errors over a set of redirected crops.
struct ConditionErrors {
  std::vector<double> none, eyeballs, full;
  int eyeballs_beat_none = 0, full_beats_eyeballs = 0;

  void Add(const RedirectColumbiaCase& c) {
    none.push_back(c.error_none), eyeballs.push_back(c.error_eyeballs), full.push_back(c.error_full);
    eyeballs_beat_none += c.error_eyeballs < c.error_none;
    full_beats_eyeballs += c.error_full < c.error_eyeballs;
  }
  nlohmann::json ToJson() const {
    const double count = static_cast<double>(none.size());
    return {{"crops", none.size()},
            {"error_none", RoundTo(Mean(none), 3)},
            {"error_eyeballs", RoundTo(Mean(eyeballs), 3)},
            {"error_full", RoundTo(Mean(full), 3)},
            {"median_none", RoundTo(Median(none), 3)},
            {"median_eyeballs", RoundTo(Median(eyeballs), 3)},
            {"median_full", RoundTo(Median(full), 3)},
            {"full_beats_eyeballs", RoundTo(full_beats_eyeballs / count, 3)},
            {"eyeballs_beat_none", RoundTo(eyeballs_beat_none / count, 3)}};
  }
};

void WriteRedirectCases(const std::string& path, const std::vector<RedirectColumbiaCase>& cases) {
  CsvWriter csv(path, {"file", "subject", "eye", "label_pitch", "label_yaw", "fit_good", "error_none", "error_eyeballs",
                       "error_full", "shift_x", "shift_y"});
  for (const RedirectColumbiaCase& c : cases) {
    csv.AddRow({c.target.path.filename().string(), c.target.subject, std::string(1, c.target.eye),
                std::to_string(c.target.vertical), std::to_string(c.target.horizontal), c.fit_good ? "1" : "0",
                fmt::format("{:.3f}", c.error_none), fmt::format("{:.3f}", c.error_eyeballs),
                fmt::format("{:.3f}", c.error_full), fmt::format("{:.2f}", c.shift.x), fmt::format("{:.2f}", c.shift.y)});
  }
  csv.Finish();
}

}  // namespace

int RunRedirectColumbiaEval(const EvalOptions& options) {
  RequireImageOutput(options.cdf_plot, "--plot");
  RequireCsvOutput(options.csv);
  RequireWritableFolder(options.out_dir, "--out-dir");
  const auto [dir, listed, crops, model, fit_options] = PrepareColumbiaRun(options);
  std::unique_ptr<Progress> progress;
  const std::filesystem::path out_dir(options.out_dir);
  Timer timer;
  const std::vector<RedirectColumbiaCase> cases = EvaluateRedirectColumbia(
      crops, model, fit_options, options.redirect,
      [&](const RedirectColumbiaCase& c, const cv::Mat& image) {
        if (!options.out_dir.empty()) WriteImage(out_dir / c.target.path.filename(), image);
      },
      [&](int done, int total) {
        if (!progress) progress = std::make_unique<Progress>("redirect-columbia", total, "crops", options.common.quiet || options.json);
        progress->Update(done);
      });
  if (progress) progress->Finish();
  if (cases.empty()) Fail(ExitCode::kBadInput, "no subject in {} has a 0P 0V 0H crop and others at head pose 0", dir.string());
  ConditionErrors overall;
  // By the target's elevation: pitch changes move the lids, yaw changes do not.
  std::map<int, ConditionErrors> by_vertical;
  for (const RedirectColumbiaCase& c : cases) overall.Add(c), by_vertical[c.target.vertical].Add(c);
  if (!options.cdf_plot.empty()) WriteImage(options.cdf_plot, ErrorCdfPlot(cases));
  if (!options.csv.empty()) WriteRedirectCases(options.csv, cases);
  const double seconds = timer.Seconds();
  if (options.json) {
    nlohmann::json result = overall.ToJson();
    result["eyelid_follow_down"] = options.redirect.eyelid_follow.down;
    result["eyelid_follow_up"] = options.redirect.eyelid_follow.up;
    result["angle_scale"] = options.redirect.angle_scale;
    result["registered"] = options.redirect.register_crops;
    for (const auto& [v, errors] : by_vertical) result["by_vertical"][std::to_string(v)] = errors.ToJson();
    result["seconds"] = RoundTo(seconds, 1);
    result["fit_options"] = FitOptionsToJson(fit_options);
    fmt::print("{}\n", result.dump());
    return 0;
  }
  fmt::print("gaze redirection on {} Columbia crops in {} (head pose 0, from each subject's 0V 0H crop)\n", cases.size(),
             dir.string());
  fmt::print("mean absolute pixel error (8-bit levels)     mean   median\n");
  fmt::print("  (a) no redirection                      {:>7.2f} {:>8.2f}\n", Mean(overall.none), Median(overall.none));
  fmt::print("  (b) eyeballs only                       {:>7.2f} {:>8.2f}\n", Mean(overall.eyeballs), Median(overall.eyeballs));
  fmt::print("  (c) eyeballs and eyelids                {:>7.2f} {:>8.2f}\n", Mean(overall.full), Median(overall.full));
  fmt::print("(b) better than (a) on {:.0f}% of crops, (c) better than (b) on {:.0f}%\n",
             100.0 * overall.eyeballs_beat_none / cases.size(), 100.0 * overall.full_beats_eyeballs / cases.size());
  fmt::print("by target elevation V     crops     (a)     (b)     (c)\n");
  for (const auto& [v, errors] : by_vertical) {
    fmt::print("  {:>+4d}                  {:>6} {:>7.2f} {:>7.2f} {:>7.2f}\n", v, errors.none.size(), Mean(errors.none),
               Mean(errors.eyeballs), Mean(errors.full));
  }
  if (options.redirect.register_crops) {
    std::vector<double> shifts;
    for (const RedirectColumbiaCase& c : cases) shifts.push_back(std::hypot(c.shift.x, c.shift.y));
    fmt::print("real crops registered to their source crops on the skin around the eye (shift median {:.2f} px, max {:.2f})\n",
               Median(shifts), *std::max_element(shifts.begin(), shifts.end()));
  } else {
    fmt::print("real crops compared as cut (unregistered)\n");
  }
  fmt::print("eyelids follow {:.2f} of each change of pitch down, {:.2f} up\n", options.redirect.eyelid_follow.down,
             options.redirect.eyelid_follow.up);
  if (options.redirect.angle_scale != 1.0) {
    fmt::print("gaze changed by {:.2f} of each label's change (not the evaluation's 1)\n", options.redirect.angle_scale);
  }
  if (!options.cdf_plot.empty()) fmt::print("error curves: {}\n", options.cdf_plot);
  if (!options.out_dir.empty()) fmt::print("redirected crops (c): {}\n", options.out_dir);
  return 0;
}

}  // namespace gazedirector::cli
