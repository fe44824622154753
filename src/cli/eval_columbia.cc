// gazedirector eval columbia: gaze estimation error on the Columbia crops.
#include <algorithm>
#include <cmath>
#include <map>
#include <type_traits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "cli/eval_options.h"
#include "gazedirector/fit/appearance_gaze.h"
#include "gazedirector/io/assets.h"
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
std::vector<ColumbiaCrop> SelectCrops(const EvalOptions& options, const std::filesystem::path& dir,
                                      const std::vector<ColumbiaCrop>& all) {
  auto listed = [](const auto& list, const auto& value) { return std::find(list.begin(), list.end(), value) != list.end(); };
  auto chosen = [&](const auto& list, const auto& value) { return list.empty() || listed(list, value); };
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

// Where the appearance gaze prior comes from in an evaluation, in words.
struct AppearanceModels {
  std::map<std::string, AppearanceGaze> by_subject;
  std::string source;
};

// The crops in the training folder: the run's own listing when it is the
// evaluated folder (the default), so that folder is listed, and warned about, once.
std::vector<ColumbiaCrop> TrainingCrops(const std::filesystem::path& training, const ColumbiaRun& run) {
  std::error_code ec;
  if (std::filesystem::equivalent(training, run.dir, ec)) return run.listed;
  return ListColumbia(training);
}

// The appearance gaze models for the run's subjects. Trained here on the
// training folder's crops (AddColumbiaCrops), each subject's own left out;
// without that folder, the model the build trained, which must not have seen them.
AppearanceModels AppearanceModelsFor(const EvalOptions& options, const ColumbiaRun& run) {
  std::vector<std::string> subjects;
  for (const ColumbiaCrop& crop : run.crops) {
    if (std::find(subjects.begin(), subjects.end(), crop.subject) == subjects.end()) subjects.push_back(crop.subject);
  }
  const std::filesystem::path training = ColumbiaDirOrDefault(options.appearance_training);
  AppearanceModels models;
  std::error_code ec;
  if (std::filesystem::is_directory(training, ec)) {
    Timer timer;
    AppearanceGazeTrainer trainer;
    const std::vector<ColumbiaCrop> pool = TrainingCrops(training, run);
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

}  // namespace

ColumbiaRun PrepareColumbiaRun(const EvalOptions& options) {
  ApplyLogLevel(options.common);
  if (options.json) spdlog::set_level(spdlog::level::warn);
  ColumbiaRun run;
  run.dir = ColumbiaDir(options);
  run.listed = ListColumbia(run.dir);
  run.crops = SelectCrops(options, run.dir, run.listed);
  run.model = EyeRegionModel::Load(Assets::Resolve(options.common.assets));
  run.fit_options = ColumbiaFitOptions(options);
  return run;
}

int RunColumbiaEval(const EvalOptions& options) {
  RequireImageOutput(options.plot, "--plot");
  RequireCsvOutput(options.csv);
  const ColumbiaRun run = PrepareColumbiaRun(options);
  const auto& [dir, listed, crops, model, fit_options] = run;
  const bool use_appearance = fit_options.weights.UsesAppearance();
  const AppearanceModels appearance = use_appearance ? AppearanceModelsFor(options, run) : AppearanceModels{};
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

}  // namespace gazedirector::cli
