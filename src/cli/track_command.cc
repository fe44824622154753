// gazedirector track: fit the eye-region model to every face of an image or
// video, and estimate gaze.
#include <cmath>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "cli/analysis_writers.h"
#include "cli/batch.h"
#include "cli/common.h"
#include "cli/fitting.h"
#include "gazedirector/fit/appearance_gaze.h"
#include "gazedirector/fit/fit_options.h"
#include "gazedirector/io/assets.h"
#include "gazedirector/io/fit_io.h"
#include "gazedirector/io/image_io.h"
#include "gazedirector/io/json_format.h"
#include "gazedirector/io/media.h"
#include "gazedirector/io/text_writer.h"
#include "gazedirector/io/video_reader.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/interrupt.h"
#include "gazedirector/util/progress.h"
#include "gazedirector/viz/draw_face.h"
#include "gazedirector/video/tracked_frame_reader.h"
#include "gazedirector/viz/draw_fit.h"

namespace gazedirector::cli {
namespace {

struct TrackOptions {
  CommonOptions common;
  CameraOptions camera;
  FittingOptions fitting;
  BatchInputOptions batch;          // the inputs as given: files, or folders of them
  std::string input;                // the one being tracked
  std::string output;
  std::string csv;
  std::string overlay;
  std::string eye_patch;
};

void Summarise(const std::string& input, const std::vector<FaceFit>& fits) {
  for (const FaceFit& fit : fits) {
    const std::array<EyeGaze, 2> gazes = EyeGazes(fit.fit.phi);
    const Eigen::Vector2d angles = GazeAngles(0.5 * (gazes[0].gaze + gazes[1].gaze));
    spdlog::info("{}face {}: gaze pitch {:.1f} yaw {:.1f} deg (head frame), angle x {:.1f} y {:.1f} deg (camera), "
                 "energy {:.4f}{}",
                 LogLabel(input), fit.face.id, fit.fit.phi.gaze_pitch(), fit.fit.phi.gaze_yaw(), angles.x() * 180 / M_PI,
                 angles.y() * 180 / M_PI, fit.fit.terms.total(), fit.fit.good ? "" : " (poor fit: " + fit.fit.note + ")");
  }
}

void WriteRecords(const TrackOptions& options, const nlohmann::json& record, const std::vector<FaceFit>& fits,
                  const std::vector<std::filesystem::path>& inputs) {
  const bool lines = std::filesystem::path(options.output).extension() == ".jsonl";
  WriteTextFile(options.output, lines ? record.dump() + "\n" : PrettyJson(record) + "\n", inputs);
  if (!options.csv.empty()) {
    CsvWriter csv(options.csv, FitCsvColumns(), inputs);
    for (const std::vector<std::string>& row : CsvRows(0, 0, fits, FitCsvRow)) csv.AddRow(row);
    csv.Finish();
  }
}

// `reader`: the appearance prior, loaded at its first use and kept for a
// batch's next eye patches.
int RunOnEyePatch(const TrackOptions& options, const FittingSetup& setup, std::optional<AppearanceGaze>& reader) {
  const std::vector<std::filesystem::path> inputs = {options.input};
  const cv::Mat crop = ReadImage(options.input);
  const int eye = options.eye_patch == "left" ? kLeftEye : kRightEye;
  // Eye patches are fitted as `eval columbia` fits its crops.
  const FitOptions fit_options = EyePatchFitOptions(options.fitting.fit);
  // The crop's appearance reading: the fit's prior on its gaze and where its
  // head yaw starts (off at weight 0), read while the eye-region model loads.
  AppearanceReading appearance;
  if (fit_options.weights.UsesAppearance()) {
    if (!reader) reader = AppearanceGaze::Load(DefaultAppearanceModelPath());
    appearance = reader->Read(crop, eye);
  }
  Fitter fitter(setup.model(), fit_options);
  FaceFit fit;
  fit.fit = fitter.FitEyePatchAt(crop, eye, 0, 0, EyePatchFraming::ReadHeadYaw(appearance), appearance);
  fit.eyes = {eye == kLeftEye, eye == kRightEye};
  fit.has_face = false;
  const Camera camera = Fitter::EyePatchCamera(crop.size());
  WriteRecords(options, FrameRecord(0, 0, {fit}, &camera), {fit}, inputs);
  if (!options.overlay.empty()) {
    cv::Mat overlay = crop.clone();
    Renderer renderer(setup.model());
    DrawFit(overlay, camera, fit.fit.phi, fit.fit.good, fit.eyes, renderer);
    WriteImage(options.overlay, overlay, inputs);
  }
  spdlog::info("{}{} eye: gaze pitch {:.1f} yaw {:.1f} deg relative to the head, head yaw {:.1f} (appearance "
               "prior {}), energy {:.4f}{} -> {}",
               LogLabel(options.input), options.eye_patch, fit.fit.phi.gaze_pitch(), EyeRegionModel::EyeYaw(fit.fit.phi, eye),
               fit.fit.phi.rotation_deg().y(),
               std::isnan(appearance.pitch) ? std::string("off")
                                            : fmt::format("pitch {:.1f} yaw {:.1f} head yaw {:.1f}", appearance.pitch,
                                                          appearance.yaw, appearance.head_yaw),
               fit.fit.terms.total(), fit.fit.good ? "" : " (poor fit: " + fit.fit.note + ")", options.output);
  return 0;
}

int RunOnImage(const TrackOptions& options, const FittingSetup& setup) {
  const std::vector<std::filesystem::path> inputs = {options.input};
  const cv::Mat image = ReadImage(options.input);
  const Camera camera = options.camera.Resolve(image.cols, image.rows);
  const std::vector<FaceFit> fits = setup.FitImage(image, camera);
  nlohmann::json record = FrameRecord(0, 0, fits, &camera);
  record["input"] = options.input;
  WriteRecords(options, record, fits, inputs);
  if (!options.overlay.empty()) {
    cv::Mat overlay = image.clone();
    Renderer renderer(setup.model());
    for (const FaceFit& fit : fits) DrawFit(overlay, camera, fit.fit.phi, fit.fit.good, fit.eyes, renderer);
    WriteImage(options.overlay, overlay, inputs);
  }
  if (fits.empty()) {
    spdlog::warn("no face found in {}", options.input);
    return static_cast<int>(ExitCode::kNoFace);
  }
  Summarise(options.input, fits);
  return 0;
}

int RunOnVideo(const TrackOptions& options, const FittingSetup& setup) {
  VideoReader reader(options.input);
  const VideoInfo& info = reader.info();
  const Camera camera = options.camera.Resolve(info.width, info.height);
  GazeTracker tracker = setup.MakeTracker();
  VideoAnalysisWriters out(options.input, info, options.output, options.csv, FitCsvColumns(), options.overlay);
  Renderer renderer(setup.model());
  Progress progress("track", info.frame_count, "frames", options.common.quiet);
  long frames_with_faces = 0, poor_fits = 0, fits_made = 0;
  TrackedFrameReader tracked_frames(reader, tracker, camera);
  TrackedFrame tracked;
  while (tracked_frames.Next(tracked)) {
    ThrowIfInterrupted();
    cv::Mat& frame = tracked.image;
    const long index = tracked.index;
    const double timestamp = tracked.timestamp_s;
    const std::vector<FaceFit> fits = tracker.FitFaces(frame, timestamp, camera, tracked.faces);
    frames_with_faces += fits.empty() ? 0 : 1;
    for (const FaceFit& fit : fits) poor_fits += fit.fit.good ? 0 : 1, ++fits_made;
    out.AddLine(FrameRecord(index, timestamp, fits, index == 0 ? &camera : nullptr));
    if (out.writes_csv()) out.AddCsvRows(CsvRows(index, timestamp, fits, FitCsvRow));
    if (out.writes_overlay()) {
      for (const FaceFit& fit : fits) DrawFit(frame, camera, fit.fit.phi, fit.fit.good, fit.eyes, renderer);
      out.AddOverlayFrame(frame, timestamp);
    }
    progress.Update(index + 1);
  }
  progress.Finish();
  WarnIfTruncated(reader, options.input);
  out.Finish();

  const long frames = reader.frame_index() + 1;
  if (frames_with_faces == 0) return NoFaceInVideo(frames, options.input);
  spdlog::info("{}{} fits in {} frames ({:.1f} frames/s), {} poor -> {}", LogLabel(options.input), fits_made, frames,
               frames / progress.elapsed_s(), poor_fits, options.output);
  return 0;
}

int RunOnOne(const TrackOptions& options, MediaKind kind, const FittingSetup& setup,
             std::optional<AppearanceGaze>& appearance) {
  if (!options.eye_patch.empty()) return RunOnEyePatch(options, setup, appearance);
  return kind == MediaKind::kImage ? RunOnImage(options, setup) : RunOnVideo(options, setup);
}

void RequireEyePatchImages(const TrackOptions& options, const std::vector<BatchInput>& inputs) {
  if (options.eye_patch.empty()) return;
  for (const BatchInput& input : inputs) {
    if (input.kind != MediaKind::kImage) {
      Fail(ExitCode::kUsage, "--eye-patch takes an image of one eye, not a video ({})", input.path.string());
    }
  }
}

// Several inputs, or folders of them: each tracked into the folders -o,
// --csv and --overlay name, as a run on it alone tracks it, the model loaded
// once. Every input and output is checked before any work.
int RunBatch(const TrackOptions& options) {
  options.camera.Check();
  const std::vector<BatchInput> inputs = ExpandBatchInputs(options.batch, {options.output, options.csv, options.overlay});
  RequireEyePatchImages(options, inputs);
  const std::vector<AnalysisOutputs> outputs = PlanAnalysisOutputs(inputs, options.output, options.csv, options.overlay);
  const FittingSetup setup = FittingSetup::Create(options.common, options.fitting);
  std::optional<AppearanceGaze> appearance;  // eye patches' prior, read once for them all
  return RunEachInput(inputs, [&](std::size_t i) {
    return RunOnOne(OptionsForInput(options, inputs[i], outputs[i]), inputs[i].kind, setup, appearance);
  });
}

int RunTrack(TrackOptions options) {
  ApplyLogLevel(options.common);
  if (IsBatch(options.batch.inputs, options.output)) return RunBatch(options);
  options.input = options.batch.inputs.front();
  const MediaKind kind = DetectMediaKind(options.input);
  RequireAnalysisOutputs(options.output, options.csv, options.overlay, kind, options.input);
  RequireEyePatchImages(options, {{options.input, kind, "", {}}});
  const FittingSetup setup = FittingSetup::Create(options.common, options.fitting);
  std::optional<AppearanceGaze> appearance;
  return RunOnOne(options, kind, setup, appearance);
}

}  // namespace

Command RegisterTrackCommand(CLI::App& root) {
  auto options = std::make_shared<TrackOptions>();
  CLI::App* app = root.add_subcommand("track", "Fit the 3D eye-region model to each face of an image or video and estimate gaze");
  AddBatchInputOptions(*app, options->batch);
  app->add_option("-o,--output", options->output,
                  "Fits: JSON lines (.jsonl, one line per frame) or one JSON document (.json, images); for several "
                  "inputs a folder, where each gets its name.json (.jsonl for a video)")
      ->required();
  app->add_option("--csv", options->csv,
                  "Also write gaze and head pose as CSV with OpenFace's column names (several inputs: a folder)");
  app->add_option("--overlay", options->overlay,
                  "Draw the fitted model and gaze rays over the input (.png/.jpg or .mp4; several inputs: a folder)");
  app->add_option("--eye-patch", options->eye_patch, "The input is a crop of one eye (as the Columbia crops): left or right")
      ->check(CLI::IsMember({"left", "right"}));
  AddFittingOptions(*app, options->fitting);
  AddCameraOptions(*app, options->camera);
  AddCommonOptions(*app, options->common);
  return {app, [options] { return RunTrack(*options); }};
}

}  // namespace gazedirector::cli
