// gazedirector eval: accuracy figures on the real data, printed as numbers.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <type_traits>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "cli/common.h"
#include "cli/fitting.h"
#include "gazedirector/eval/columbia.h"
#include "gazedirector/eval/landmark_accuracy.h"
#include "gazedirector/eval/redirect_columbia.h"
#include "gazedirector/fit/fit_options.h"
#include "gazedirector/fit/iris_alignment.h"
#include "gazedirector/io/assets.h"
#include "gazedirector/io/image_io.h"
#include "gazedirector/io/json_format.h"
#include "gazedirector/io/text_writer.h"
#include "gazedirector/io/video_reader.h"
#include "gazedirector/redirect/gaze_target.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/interrupt.h"
#include "gazedirector/util/progress.h"
#include "gazedirector/util/statistics.h"
#include "gazedirector/util/timer.h"
#include "gazedirector/viz/plot.h"

namespace gazedirector::cli {
namespace {

struct EvalOptions {
  CommonOptions common;
  bool json = false;
  std::string landmarks_xml;
  std::vector<double> landmark_turns = {0};
  std::string columbia_dir;
  std::string plot = "eval_columbia.png";
  std::string csv;
  std::vector<std::string> subjects;
  std::vector<std::string> excluded_subjects;
  std::vector<int> poses;
  int every = 1;
  int threads = 2;
  int iterations = 0;
  std::vector<std::string> fit_options;
  bool known_head_pose = false;
  std::string appearance_training;
  std::string out_dir;
  RedirectColumbiaOptions redirect;
  std::string cdf_plot = "eval_redirect_columbia.png";
  std::string iris_input;
  std::string iris_fits;
  FittingOptions fitting;
  CameraOptions camera;
};

// Mean and median absolute yaw and pitch errors of a set of estimates
// (crops or photos) in one frame.
struct ErrorSummary {
  int count = 0;
  double yaw_mean = 0, yaw_median = 0, pitch_mean = 0, pitch_median = 0;
  // the always-zero predictor: straight ahead in the head, or into the camera
  double zero_yaw_mean = 0, zero_yaw_median = 0, zero_pitch_mean = 0, zero_pitch_median = 0;
};

template <typename Estimate>
ErrorSummary Summarise(const std::vector<const Estimate*>& estimates, GazeFrame frame) {
  std::vector<double> yaw, pitch, zero_yaw, zero_pitch;
  for (const Estimate* estimate : estimates) {
    yaw.push_back(estimate->Reading(frame).yaw_error);
    pitch.push_back(estimate->Reading(frame).pitch_error);
    const Eigen::Vector2d label = estimate->crop.Label(frame);
    zero_yaw.push_back(std::abs(label.y()));
    zero_pitch.push_back(std::abs(label.x()));
  }
  return {static_cast<int>(estimates.size()), Mean(yaw),         Median(yaw),       Mean(pitch),      Median(pitch),
          Mean(zero_yaw),                      Median(zero_yaw), Mean(zero_pitch), Median(zero_pitch)};
}

// Overall and per head pose.
struct PoseSummaries {
  ErrorSummary all;
  std::map<int, ErrorSummary> by_pose;
};

// One summary per value of `key` (of an estimate's crop), in the key's order.
template <typename Estimate, typename Key>
auto SummariseBy(const std::vector<Estimate>& estimates, GazeFrame frame, Key key) {
  using Value = std::decay_t<decltype(key(estimates.front().crop))>;
  std::map<Value, std::vector<const Estimate*>> groups;
  for (const Estimate& estimate : estimates) groups[key(estimate.crop)].push_back(&estimate);
  std::map<Value, ErrorSummary> summaries;
  for (const auto& [value, group] : groups) summaries[value] = Summarise(group, frame);
  return summaries;
}

template <typename Estimate>
PoseSummaries SummariseByPose(const std::vector<Estimate>& estimates, GazeFrame frame) {
  std::vector<const Estimate*> all;
  for (const Estimate& estimate : estimates) all.push_back(&estimate);
  return {Summarise(all, frame), SummariseBy(estimates, frame, [](const ColumbiaCrop& crop) { return crop.head_pose; })};
}

// `counted` names what the summary counts: "photos" (the face's gaze) or "crops" (one eye).
nlohmann::json ToJson(const ErrorSummary& s, const std::string& counted) {
  return {{counted, s.count},
          {"yaw_mean_deg", RoundTo(s.yaw_mean, 3)},
          {"yaw_median_deg", RoundTo(s.yaw_median, 3)},
          {"pitch_mean_deg", RoundTo(s.pitch_mean, 3)},
          {"pitch_median_deg", RoundTo(s.pitch_median, 3)},
          {"zero_yaw_mean_deg", RoundTo(s.zero_yaw_mean, 3)},
          {"zero_yaw_median_deg", RoundTo(s.zero_yaw_median, 3)},
          {"zero_pitch_mean_deg", RoundTo(s.zero_pitch_mean, 3)},
          {"zero_pitch_median_deg", RoundTo(s.zero_pitch_median, 3)}};
}

// Photometric energy and gaze error against the Gauss-Newton iteration:
// median and interquartile band, as in the paper's figure.
cv::Mat ConvergencePlot(const std::vector<ColumbiaFit>& fits) {
  std::vector<std::vector<double>> energies, errors;
  std::size_t length = 0;
  for (const ColumbiaFit& fit : fits) {
    energies.push_back(fit.energy_by_iteration);
    errors.push_back(fit.gaze_error_by_iteration);
    length = std::max(length, fit.energy_by_iteration.size());
  }
  std::vector<double> x;
  for (std::size_t i = 0; i < length; ++i) x.push_back(static_cast<double>(i));
  const QuantileCurves energy = QuantilesByIndex(energies, static_cast<int>(length));
  const QuantileCurves error = QuantilesByIndex(errors, static_cast<int>(length));
  LinePlot energy_plot("Photometric energy E_img", "Gauss-Newton iteration", "E_img (mean squared RGB error)");
  energy_plot.AddSeries("median, IQR", x, energy.median, cv::Scalar(180, 90, 30), energy.q25, energy.q75);
  LinePlot error_plot("Gaze error", "Gauss-Newton iteration", "angle to the label (degrees)");
  error_plot.AddSeries("median, IQR", x, error.median, cv::Scalar(40, 40, 200), error.q25, error.q75);
  return SideBySide({energy_plot.Draw(), error_plot.Draw()});
}

std::filesystem::path ColumbiaDir(const EvalOptions& options) {
  return ColumbiaDirOrDefault(options.columbia_dir);
}

// The crops of the chosen subjects (less the excluded ones) and head poses
// (all when none are chosen), from every `every`th photo (both eyes of a photo stay together).
std::vector<ColumbiaCrop> SelectCrops(const EvalOptions& options, const std::filesystem::path& dir) {
  auto listed = [](const auto& list, const auto& value) { return std::find(list.begin(), list.end(), value) != list.end(); };
  auto chosen = [&](const auto& list, const auto& value) { return list.empty() || listed(list, value); };
  const std::vector<ColumbiaCrop> all = ListColumbia(dir);
  // A subject named but absent is most likely a typo; say so rather than quietly evaluate something else.
  for (const std::vector<std::string>* named : {&options.subjects, &options.excluded_subjects}) {
    for (const std::string& subject : *named) {
      if (std::none_of(all.begin(), all.end(), [&](const ColumbiaCrop& crop) { return crop.subject == subject; })) {
        spdlog::warn("subject {} has no crops in {}", subject, dir.string());
      }
    }
  }
  std::vector<ColumbiaCrop> crops;
  int photo_index = -1;
  std::string last_photo;
  for (const ColumbiaCrop& crop : all) {
    if (!chosen(options.subjects, crop.subject) || listed(options.excluded_subjects, crop.subject) ||
        !chosen(options.poses, crop.head_pose)) {
      continue;
    }
    if (crop.Photo() != last_photo) last_photo = crop.Photo(), ++photo_index;
    if (photo_index % options.every == 0) crops.push_back(crop);
  }
  if (crops.empty()) Fail(ExitCode::kBadInput, "no crops in {} match the filters", dir.string());
  return crops;
}

// The fitter's options for the 64x64 crops.
FitOptions ColumbiaFitOptions(const EvalOptions& options) {
  std::vector<std::string> assignments;
  if (options.iterations > 0) assignments.push_back(fmt::format("iterations={}", options.iterations));
  assignments.insert(assignments.end(), options.fit_options.begin(), options.fit_options.end());
  return EyePatchFitOptions(assignments);
}

// What both Columbia evaluations start from.
struct ColumbiaRun {
  std::filesystem::path dir;
  std::vector<ColumbiaCrop> crops;
  std::shared_ptr<const EyeRegionModel> model;
  FitOptions fit_options;
};

ColumbiaRun PrepareColumbiaRun(const EvalOptions& options) {
  ApplyLogLevel(options.common);
  if (options.json) spdlog::set_level(spdlog::level::warn);
  ColumbiaRun run;
  run.dir = ColumbiaDir(options);
  run.crops = SelectCrops(options, run.dir);
  run.model = EyeRegionModel::Load(Assets::Resolve(options.common.assets));
  run.fit_options = ColumbiaFitOptions(options);
  return run;
}

// Where the appearance gaze prior comes from in an evaluation, in words.
struct AppearanceModels {
  std::map<std::string, AppearanceGaze> by_subject;
  std::string source;
};

// The appearance gaze models for the crops' subjects. Trained here on the
// training folder's crops (AddColumbiaCrops), each subject's own left out;
// without that folder, the model the build trained, which must not have seen them.
AppearanceModels AppearanceModelsFor(const EvalOptions& options, const std::vector<ColumbiaCrop>& crops) {
  std::vector<std::string> subjects;
  for (const ColumbiaCrop& crop : crops) {
    if (std::find(subjects.begin(), subjects.end(), crop.subject) == subjects.end()) subjects.push_back(crop.subject);
  }
  const std::filesystem::path training = ColumbiaDirOrDefault(options.appearance_training);
  AppearanceModels models;
  std::error_code ec;
  if (std::filesystem::is_directory(training, ec)) {
    Timer timer;
    AppearanceGazeTrainer trainer;
    const std::vector<ColumbiaCrop> pool = ListColumbia(training);
    AddColumbiaCrops(pool, trainer);
    models.by_subject = LeaveSubjectOut(trainer, subjects);
    const long seen = std::count_if(subjects.begin(), subjects.end(),
                                    [&](const std::string& subject) { return trainer.Has(subject); });
    std::string left_out = fmt::format("the {} of them evaluated each left out", seen);
    if (seen == 0) left_out = "none of them evaluated";
    if (seen == static_cast<long>(subjects.size())) left_out = "each evaluated subject left out";
    models.source = fmt::format("trained on {} crops of {} subjects in {}, {}", pool.size(),
                                trainer.subjects().size(), training.string(), left_out);
    spdlog::info("appearance gaze: {} ({:.1f} s)", models.source, timer.Seconds());
    return models;
  }
  if (!options.appearance_training.empty()) {
    Fail(ExitCode::kBadInput, "--appearance-training {}: no such folder", training.string());
  }
  const std::filesystem::path shipped = DefaultAppearanceModelPath();
  const AppearanceGaze model = AppearanceGaze::Load(shipped);
  for (const std::string& subject : subjects) {
    if (std::find(model.subjects().begin(), model.subjects().end(), subject) != model.subjects().end()) {
      Fail(ExitCode::kUsage,
           "{} was trained on subject {}, so its figures would be in-sample; pass --appearance-training DIR (the crops "
           "to train on, each evaluated subject left out) or --fit appearance_pitch=0 appearance_yaw=0",
           shipped.string(), subject);
    }
    models.by_subject.emplace(subject, model);
  }
  models.source = fmt::format("{} (trained on {} subjects, none of these)", shipped.string(), model.subjects().size());
  return models;
}

// What `eval columbia` reports: the fits and their summaries.
struct ColumbiaReport {
  std::vector<ColumbiaFit> fits;
  std::vector<ColumbiaPhoto> photos;
  PoseSummaries by_photo, by_crop, by_photo_camera;
  std::map<std::string, ErrorSummary> by_subject;
  SubjectResampling spread;
  std::vector<HeadYawReadings> head_readings;  // empty where the head's yaw was given
  double fits_per_s = 0;
  std::string appearance_source;  // "off" without the prior
};

ColumbiaReport SummariseColumbia(std::vector<ColumbiaFit> fits, double seconds, bool known_head_pose) {
  ColumbiaReport report;
  report.fits = std::move(fits);
  report.photos = CombineEyes(report.fits);
  report.by_photo = SummariseByPose(report.photos, GazeFrame::kHead);
  report.by_crop = SummariseByPose(report.fits, GazeFrame::kHead);
  report.by_photo_camera = SummariseByPose(report.photos, GazeFrame::kCamera);
  report.by_subject = SummariseBy(report.photos, GazeFrame::kHead, [](const ColumbiaCrop& crop) { return crop.subject; });
  report.spread = ResampleSubjects(report.photos, GazeFrame::kHead);
  // Given the head's yaw, the fits' readings carry that yaw, not a reading.
  if (!known_head_pose) report.head_readings = SummariseHeadYawReadings(report.fits);
  report.fits_per_s = report.fits.size() / seconds;
  return report;
}

void WriteColumbiaCsv(const std::string& path, const ColumbiaReport& report) {
  CsvWriter csv(path, {"file", "subject", "head_pose", "label_pitch", "label_yaw", "eye", "head_label_pitch",
                       "head_label_yaw", "pitch", "yaw", "pitch_error", "yaw_error", "head_pitch", "head_yaw",
                       "camera_pitch", "camera_yaw", "camera_pitch_error", "camera_yaw_error", "seconds", "face_pitch",
                       "face_yaw", "face_camera_pitch", "face_camera_yaw", "energy", "appearance_pitch",
                       "appearance_yaw", "appearance_head_yaw"});
  std::map<std::string, const ColumbiaPhoto*> photo_of;
  for (const ColumbiaPhoto& photo : report.photos) photo_of[photo.crop.Photo()] = &photo;
  auto number = [](double value) { return std::isnan(value) ? std::string() : fmt::format("{:.3f}", value); };
  for (const ColumbiaFit& fit : report.fits) {
    const ColumbiaPhoto& photo = *photo_of.at(fit.crop.Photo());
    const Eigen::Vector2d head_label = fit.crop.Label(GazeFrame::kHead);
    csv.AddRow({fit.crop.path.filename().string(), fit.crop.subject, std::to_string(fit.crop.head_pose),
                std::to_string(fit.crop.vertical), std::to_string(fit.crop.horizontal), std::string(1, fit.crop.eye),
                number(head_label.x()), number(head_label.y()), number(fit.in_head.pitch), number(fit.in_head.yaw),
                number(fit.in_head.pitch_error), number(fit.in_head.yaw_error), number(fit.head_pitch),
                number(fit.head_yaw), number(fit.in_camera.pitch), number(fit.in_camera.yaw),
                number(fit.in_camera.pitch_error), number(fit.in_camera.yaw_error), number(fit.seconds),
                number(photo.in_head.pitch), number(photo.in_head.yaw), number(photo.in_camera.pitch),
                number(photo.in_camera.yaw), fmt::format("{:.6f}", fit.energy), number(fit.appearance.pitch),
                number(fit.appearance.yaw), number(fit.appearance.head_yaw)});
  }
  csv.Finish();
}

// One JSON object; its headline figures are the faces' gazes (both eyes) relative to the head, as the paper's.
void PrintColumbiaJson(const ColumbiaReport& report, const EvalOptions& options, const FitOptions& fit_options) {
  nlohmann::json result = ToJson(report.by_photo.all, "photos");
  result["crops"] = report.fits.size();
  result["one_eye"] = ToJson(report.by_crop.all, "crops");
  result["camera_frame"] = ToJson(report.by_photo_camera.all, "photos");
  result["fits_per_s"] = RoundTo(report.fits_per_s, 2);
  result["threads"] = options.threads;
  result["head_pose"] = options.known_head_pose ? "known (-P from the file name)" : "estimated";
  result["fit_options"] = FitOptionsToJson(fit_options);
  result["appearance_prior"] = report.appearance_source;
  for (const auto& [subject, summary] : report.by_subject) result["by_subject"][subject] = ToJson(summary, "photos");
  const SubjectResampling& spread = report.spread;
  result["subject_resampling"] = {{"subjects", spread.subjects},
                                  {"yaw_mean_p5_deg", RoundTo(spread.yaw_low, 3)},
                                  {"yaw_mean_p95_deg", RoundTo(spread.yaw_high, 3)},
                                  {"pitch_mean_p5_deg", RoundTo(spread.pitch_low, 3)},
                                  {"pitch_mean_p95_deg", RoundTo(spread.pitch_high, 3)}};
  for (const auto& [pose, summary] : report.by_photo.by_pose) {
    nlohmann::json& entry = result["by_head_pose"][std::to_string(pose)];
    entry = ToJson(summary, "photos");
    entry["one_eye"] = ToJson(report.by_crop.by_pose.at(pose), "crops");
    entry["camera_frame"] = ToJson(report.by_photo_camera.by_pose.at(pose), "photos");
  }
  for (const HeadYawReadings& h : report.head_readings) {
    result["head_yaw_reading"][std::to_string(h.head_pose)] = {
        {"photos", h.photos},
        {"subjects", h.subjects},
        {"mean_deg", RoundTo(h.mean_reading, 3)},
        {"error_mean_deg", RoundTo(h.mean_error, 3)},
        {"abs_error_mean_deg", RoundTo(h.mean_abs_error, 3)},
        {"subject_spread_deg", RoundTo(h.subject_spread, 3)},
        {"within_subject_deg", RoundTo(h.within_subject, 3)}};
  }
  fmt::print("{}\n", result.dump());
}

using ErrorRows = std::vector<std::pair<std::string, ErrorSummary>>;

void PrintErrorTable(const ErrorRows& rows, const std::string& key, const std::string& unit) {
  fmt::print("{:>10} {:>6}   {:>9} {:>9}   {:>9} {:>9}   {:>15} {:>9}   {:>15} {:>9}\n", key, unit, "yaw mean", "median",
             "pitch mean", "median", "zero yaw mean", "median", "zero pitch mean", "median");
  for (const auto& [name, s] : rows) {
    fmt::print("{:>10} {:>6}   {:>9.2f} {:>9.2f}   {:>9.2f} {:>9.2f}   {:>15.2f} {:>9.2f}   {:>15.2f} {:>9.2f}\n", name,
               s.count, s.yaw_mean, s.yaw_median, s.pitch_mean, s.pitch_median, s.zero_yaw_mean, s.zero_yaw_median,
               s.zero_pitch_mean, s.zero_pitch_median);
  }
}

void PrintByPoseTable(const PoseSummaries& summaries, const std::string& unit) {
  ErrorRows rows;
  for (const auto& [pose, summary] : summaries.by_pose) rows.emplace_back(std::to_string(pose), summary);
  rows.emplace_back("all", summaries.all);
  PrintErrorTable(rows, "head pose", unit);
}

void PrintHeadYawReadings(const std::vector<HeadYawReadings>& readings) {
  if (readings.empty()) return;
  fmt::print("the head's yaw read from a photo's crops (the reading its fits were given), by head pose; error: the\n"
             "reading less -P; subjects' spread: the s.d. of the subjects' mean readings; within a subject: a photo's\n"
             "mean distance from its subject's mean\n");
  fmt::print("{:>10} {:>6} {:>8}   {:>9} {:>10} {:>12}   {:>16} {:>16}\n", "head pose", "photos", "subjects", "reading",
             "mean error", "mean |error|", "subjects' spread", "within a subject");
  for (const HeadYawReadings& h : readings) {
    fmt::print("{:>10} {:>6} {:>8}   {:>9.2f} {:>10.2f} {:>12.2f}   {:>16.2f} {:>16.2f}\n", h.head_pose, h.photos,
               h.subjects, h.mean_reading, h.mean_error, h.mean_abs_error, h.subject_spread, h.within_subject);
  }
}

void PrintColumbiaTables(const ColumbiaReport& report, const EvalOptions& options, const std::filesystem::path& dir) {
  fmt::print("gaze error on {} photos ({} crops) in {} (degrees)\n", report.photos.size(), report.fits.size(),
             dir.string());
  fmt::print("labels: relative to the camera (0V 0H looks into the lens at every head pose); in the head's frame\n"
             "they are turned by the head's yaw, -P\n");
  fmt::print("relative to the head, the face's gaze: the mean of both eyes' fits where both crops are there\n");
  PrintByPoseTable(report.by_photo, "photos");
  fmt::print("relative to the head, one eye: each crop on its own\n");
  PrintByPoseTable(report.by_crop, "crops");
  fmt::print("relative to the camera, the face's gaze (zero: looking into the lens)\n");
  PrintByPoseTable(report.by_photo_camera, "photos");
  fmt::print("relative to the head, the face's gaze, by subject\n");
  PrintErrorTable(ErrorRows(report.by_subject.begin(), report.by_subject.end()), "subject", "photos");
  const SubjectResampling& spread = report.spread;
  if (spread.subjects > 1) {
    fmt::print("resampling the {} subjects ({} draws with replacement), 5th-95th percentile of the mean: yaw "
               "{:.2f}-{:.2f}, pitch {:.2f}-{:.2f}\n",
               spread.subjects, spread.draws, spread.yaw_low, spread.yaw_high, spread.pitch_low, spread.pitch_high);
  }
  PrintHeadYawReadings(report.head_readings);
  fmt::print("head pose: {}\n", options.known_head_pose ? "known (-P from the file names)"
                                                         : "estimated from the crops (the mean of a photo's two readings)");
  fmt::print("appearance gaze prior: {}\n", report.appearance_source);
  fmt::print("fits per second: {:.2f} ({} threads)\n", report.fits_per_s, options.threads);
  if (!options.plot.empty()) fmt::print("convergence plot: {}\n", options.plot);
}

int RunColumbiaEval(const EvalOptions& options) {
  RequireImageOutput(options.plot, "--plot");
  RequireCsvOutput(options.csv);
  const auto [dir, crops, model, fit_options] = PrepareColumbiaRun(options);
  const bool use_appearance = fit_options.weights.UsesAppearance();
  const AppearanceModels appearance = use_appearance ? AppearanceModelsFor(options, crops) : AppearanceModels{};
  Progress progress("columbia", static_cast<long>(crops.size()), "crops", options.common.quiet || options.json);
  Timer timer;
  std::vector<ColumbiaFit> fits =
      FitColumbia(crops, model, fit_options, options.threads, options.known_head_pose,
                  [&](int done) { progress.Update(done); }, use_appearance ? &appearance.by_subject : nullptr);
  const double seconds = timer.Seconds();
  progress.Finish();

  ColumbiaReport report = SummariseColumbia(std::move(fits), seconds, options.known_head_pose);
  report.appearance_source = use_appearance ? appearance.source : "off";
  if (!options.plot.empty()) WriteImage(options.plot, ConvergencePlot(report.fits));
  if (!options.csv.empty()) WriteColumbiaCsv(options.csv, report);
  if (options.json) {
    PrintColumbiaJson(report, options, fit_options);
  } else {
    PrintColumbiaTables(report, options, dir);
  }
  return 0;
}

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

int RunRedirectColumbiaEval(const EvalOptions& options) {
  RequireImageOutput(options.cdf_plot, "--plot");
  RequireCsvOutput(options.csv);
  RequireWritableFolder(options.out_dir, "--out-dir");
  const auto [dir, crops, model, fit_options] = PrepareColumbiaRun(options);
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

// The fits of one frame: read from a fits file, or tracked now.
std::vector<StoredFit> FitsOfFrame(const std::optional<FitsFile>& stored, long index, const cv::Mat& frame,
                                   double timestamp_s, const Camera& camera, GazeTracker& tracker, bool video) {
  if (stored) {
    const auto found = stored->frames.find(index);
    return found == stored->frames.end() ? std::vector<StoredFit>() : found->second.faces;
  }
  std::vector<StoredFit> fits;
  const std::vector<FaceFit> tracked = video ? tracker.ProcessFrame(frame, timestamp_s, camera) : tracker.ProcessImage(frame, camera);
  for (const FaceFit& fit : tracked) fits.push_back(StoredFit::Of(fit));
  return fits;
}

int RunIrisEval(const EvalOptions& options) {
  ApplyLogLevel(options.common);
  const MediaKind kind = DetectMediaKind(options.iris_input);
  RequireCsvOutput(options.csv, {options.iris_input});
  std::optional<FitsFile> stored;
  if (!options.iris_fits.empty()) stored = ReadFits(options.iris_fits);
  const FittingSetup setup = FittingSetup::Create(options.common, options.fitting);
  GazeTracker tracker = setup.MakeTracker();
  Renderer renderer(setup.model);
  std::optional<CsvWriter> csv;
  if (!options.csv.empty()) {
    csv.emplace(options.csv, std::vector<std::string>{"frame", "face_id", "eye", "iris_misalignment"},
                std::vector<std::filesystem::path>{options.iris_input});
  }
  std::vector<double> distances;
  long frames = 0, evaluated = 0;
  auto evaluate = [&](const cv::Mat& frame, long index, double timestamp_s, const Camera& camera) {
    const std::vector<StoredFit> fits = FitsOfFrame(stored, index, frame, timestamp_s, camera, tracker, kind == MediaKind::kVideo);
    if (index % options.every != 0) return;
    ++evaluated;
    for (const StoredFit& fit : fits) {
      if (fit.eyes_closed) continue;
      const std::array<double, 2> misalignment = IrisMisalignment(frame, camera, fit.phi, fit.eyes, renderer);
      for (int eye = 0; eye < 2; ++eye) {
        if (!std::isfinite(misalignment[eye])) continue;
        distances.push_back(misalignment[eye]);
        if (csv) {
          csv->AddRow({std::to_string(index), std::to_string(fit.face_id), eye == kLeftEye ? "left" : "right",
                       fmt::format("{:.4f}", misalignment[eye])});
        }
      }
    }
  };
  auto camera_for = [&](int width, int height) {
    if (stored) RequireFitsOfSize(*stored, width, height);
    return stored && stored->camera ? *stored->camera : options.camera.Resolve(width, height);
  };
  if (kind == MediaKind::kImage) {
    const cv::Mat image = ReadSourceImage(options.iris_input).bgr;
    evaluate(image, 0, 0.0, camera_for(image.cols, image.rows));
    frames = 1;
  } else {
    VideoReader reader(options.iris_input);
    const Camera camera = camera_for(reader.info().width, reader.info().height);
    Progress progress("eval iris", reader.info().frame_count, "frames", options.common.quiet || options.json);
    cv::Mat frame;
    while (reader.Read(frame)) {
      ThrowIfInterrupted();
      evaluate(frame, reader.frame_index(), reader.timestamp_s(), camera);
      progress.Update(reader.frame_index() + 1);
    }
    progress.Finish();
    frames = reader.frame_index() + 1;
  }
  if (distances.empty()) Fail(ExitCode::kNoFace, "no open fitted eye in {}", options.iris_input);
  if (csv) csv->Finish();
  const double median = Median(distances), p90 = Quantile(distances, 0.9), mean = Mean(distances);
  if (options.json) {
    fmt::print("{}\n", nlohmann::json{{"frames", frames}, {"frames_evaluated", evaluated}, {"eyes", distances.size()},
                                      {"median", median}, {"p90", p90}, {"mean", mean}}
                           .dump());
    return 0;
  }
  fmt::print("fitted iris to the photo's darkest eyeball pixels, in iris radii ({}; {} of {} frames, {} open eyes{})\n",
             options.iris_input, evaluated, frames, distances.size(), stored ? ", fits from " + options.iris_fits : "");
  fmt::print("  median {:.2f}   90th percentile {:.2f}   mean {:.2f}\n", median, p90, mean);
  fmt::print("  (about 0.1-0.4 on the iris; 1 or more: the fit lost it)\n");
  if (csv) fmt::print("each eye: {}\n", options.csv);
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
  landmarks->add_option("--turn", options->landmark_turns,
                        "Also turn each photo by these angles in degrees first (e.g. 0 30 60 90): tilted faces")
      ->check(CLI::Range(-180.0, 180.0))
      ->capture_default_str();
  AddCommonOptions(*landmarks, options->common);
  // What both Columbia evaluations take: the crops, which subjects, the fitter's options.
  auto add_columbia_options = [&options](CLI::App* command) {
    command->add_option("dir", options->columbia_dir, "Folder of crops (default: ../shared/data/columbia-eyes)");
    command->add_flag("--json", options->json, "Print one JSON object");
    command->add_option("--subjects", options->subjects, "Only these subjects (e.g. 0001 0002)");
    command->add_option("--exclude-subjects", options->excluded_subjects,
                        "Leave these subjects out (the paper left out people wearing glasses)");
    command->add_option("--fit", options->fit_options,
                        "Fitter options as name=value (" + fmt::format("{}", fmt::join(ListFitOptions(), ", ")) + ")");
  };
  CLI::App* columbia = app->add_subcommand("columbia", "Gaze estimation error on Columbia Gaze eye crops (file-name labels)");
  add_columbia_options(columbia);
  columbia->add_option("--plot", options->plot, "Write the convergence figure here (PNG)")->capture_default_str();
  columbia->add_option("--csv", options->csv, "Write every crop's estimate and error here");
  columbia->add_option("--poses", options->poses, "Only these head poses (e.g. 0 15)");
  columbia->add_option("--every", options->every, "Take every Nth photo, both eyes' crops (a quick, spread-out sample)")
      ->check(CLI::Range(1, 1000000));
  columbia->add_option("--threads", options->threads, "Fits side by side")->check(CLI::Range(1, 64))->capture_default_str();
  columbia->add_option("--iterations", options->iterations, "Gauss-Newton iterations per fit (default: the fitter's)");
  columbia->add_option("--appearance-training", options->appearance_training,
                       "Labelled crops to train the appearance gaze prior on, each evaluated subject left out "
                       "(default: ../shared/data/columbia-eyes; without it, the model the build trained, build/release/models/appearance_gaze.cbor)");
  columbia->add_flag("--known-head-pose", options->known_head_pose,
                     "Give the fitter the head's yaw from the file name (-P) instead of estimating it from one eye");
  AddCommonOptions(*columbia, options->common);

  CLI::App* redirect = app->add_subcommand("redirect-columbia",
                                           "Redirection error on Columbia crops: each subject's 0V 0H crop redirected to the other gazes");
  add_columbia_options(redirect);
  redirect->add_option("--plot", options->cdf_plot, "Write the cumulative error curves here (PNG)")->capture_default_str();
  redirect->add_option("--out-dir", options->out_dir, "Write every redirected crop (c), framed as its source (unregistered), under the name of the real crop it imitates");
  redirect->add_option("--csv", options->csv, "Write every crop's three errors here");
  redirect->add_option("--eyelid-follow-down", options->redirect.eyelid_follow.down,
                       "How far the eyelids follow a downward change of pitch (0: not at all, 1: fully)")
      ->check(CLI::Range(0.0, 1.5))
      ->capture_default_str();
  redirect->add_option("--eyelid-follow-up", options->redirect.eyelid_follow.up, "The same for an upward change")
      ->check(CLI::Range(0.0, 1.5))
      ->capture_default_str();
  redirect->add_flag("--no-register", [options](std::int64_t) { options->redirect.register_crops = false; },
                     "Compare with the real crops as cut, without registering them to the source crop on the skin around the eye");
  redirect->add_option("--angle-scale", options->redirect.angle_scale,
                       "Redirect by this fraction of each label's change of gaze (analysis; the evaluation is 1)")
      ->check(CLI::Range(0.0, 2.0))
      ->capture_default_str();
  AddCommonOptions(*redirect, options->common);

  CLI::App* iris = app->add_subcommand(
      "iris", "How far each fitted iris sits from the photo's own (no labels): images and videos");
  iris->add_option("input", options->iris_input, "Image or video")->required();
  iris->add_option("--fits", options->iris_fits, "Fits from `gazedirector track` of this input (default: track it now)");
  iris->add_option("--every", options->every, "Measure every Nth frame (a video is still tracked frame by frame)")
      ->check(CLI::Range(1, 1000000));
  iris->add_flag("--json", options->json, "Print one JSON object");
  iris->add_option("--csv", options->csv, "Write each measured eye's distance here (frame, face_id, eye, iris_misalignment)");
  AddFittingOptions(*iris, options->fitting);
  AddCameraOptions(*iris, options->camera);
  AddCommonOptions(*iris, options->common);
  return {app, [options, landmarks, columbia, redirect, iris] {
            if (landmarks->parsed()) return RunLandmarkEval(*options);
            if (columbia->parsed()) return RunColumbiaEval(*options);
            if (redirect->parsed()) return RunRedirectColumbiaEval(*options);
            if (iris->parsed()) return RunIrisEval(*options);
            return static_cast<int>(ExitCode::kUsage);
          }};
}

}  // namespace gazedirector::cli
