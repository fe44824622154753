// gazedirector landmarks: faces, 68 landmarks and head pose in an image or video.
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "cli/analysis_writers.h"
#include "cli/batch.h"
#include "cli/common.h"
#include "gazedirector/face/face_io.h"
#include "gazedirector/face/face_tracker.h"
#include "gazedirector/io/assets.h"
#include "gazedirector/io/image_io.h"
#include "gazedirector/io/json_format.h"
#include "gazedirector/io/media.h"
#include "gazedirector/io/text_writer.h"
#include "gazedirector/io/video_reader.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/interrupt.h"
#include "gazedirector/util/progress.h"
#include "gazedirector/viz/draw_face.h"

namespace gazedirector::cli {
namespace {

struct LandmarksOptions {
  CommonOptions common;
  CameraOptions camera;
  BatchInputOptions batch;          // the inputs as given: files, or folders of them
  std::string input;                // the one being searched
  std::string output;
  std::string csv;
  std::string overlay;
  bool largest = false;
  bool no_smoothing = false;
  HeadPoseMethod head_pose = HeadPoseMethod::kPerspectiveNPoint;
};

int RunOnImage(const LandmarksOptions& options, FaceTracker& tracker) {
  const std::vector<std::filesystem::path> inputs = {options.input};
  const cv::Mat image = ReadImage(options.input);
  const Camera camera = options.camera.Resolve(image.cols, image.rows);
  const std::vector<Face> faces = tracker.DetectFaces(image, camera);

  nlohmann::json document = {{"input", options.input}, {"width", image.cols}, {"height", image.rows},
                             {"camera", ToJson(camera)}, {"faces", nlohmann::json::array()}};
  for (const Face& face : faces) document["faces"].push_back(ToJson(face));
  std::optional<CsvWriter> csv;
  if (!options.csv.empty()) {
    csv.emplace(options.csv, FaceCsvColumns(), inputs);
    for (const std::vector<std::string>& row : CsvRows(0, 0, faces, FaceCsvRow)) csv->AddRow(row);
  }
  cv::Mat overlay;
  if (!options.overlay.empty()) {
    overlay = image.clone();
    for (const Face& face : faces) DrawFace(overlay, face, camera);
  }
  WriteTextFile(options.output, PrettyJson(document) + "\n", inputs);
  if (csv) csv->Finish();
  if (!overlay.empty()) WriteImage(options.overlay, overlay, inputs);

  if (faces.empty()) {
    spdlog::warn("no face found in {}", options.input);
    return static_cast<int>(ExitCode::kNoFace);
  }
  spdlog::info("{}{} face{} -> {}", LogLabel(options.input), faces.size(), faces.size() == 1 ? "" : "s", options.output);
  return 0;
}

int RunOnVideo(const LandmarksOptions& options, FaceTracker& tracker) {
  VideoReader reader(options.input);
  const VideoInfo& info = reader.info();
  const Camera camera = options.camera.Resolve(info.width, info.height);
  VideoAnalysisWriters out(options.input, info, options.output, options.csv, FaceCsvColumns(), options.overlay);

  Progress progress("landmarks", info.frame_count, "frames", options.common.quiet);
  cv::Mat frame;
  long frames_with_faces = 0;
  while (reader.Read(frame)) {
    ThrowIfInterrupted();
    const long index = reader.frame_index();
    const double timestamp = reader.timestamp_s();
    const std::vector<Face> faces = tracker.TrackFrame(frame, timestamp, camera);
    frames_with_faces += faces.empty() ? 0 : 1;

    nlohmann::json line = {{"frame", index}, {"timestamp", RoundTo(timestamp, 4)}, {"faces", nlohmann::json::array()}};
    if (index == 0) line["camera"] = ToJson(camera);
    for (const Face& face : faces) line["faces"].push_back(ToJson(face));
    out.AddLine(line);
    if (out.writes_csv()) out.AddCsvRows(CsvRows(index, timestamp, faces, FaceCsvRow));
    if (out.writes_overlay()) {
      for (const Face& face : faces) DrawFace(frame, face, camera);
      out.AddOverlayFrame(frame, timestamp);
    }
    progress.Update(index + 1);
  }
  progress.Finish();
  WarnIfTruncated(reader, options.input);
  out.Finish();

  const long frames = reader.frame_index() + 1;
  if (frames_with_faces == 0) return NoFaceInVideo(frames, options.input);
  spdlog::info("{}faces in {} of {} frames -> {}", LogLabel(options.input), frames_with_faces, frames, options.output);
  return 0;
}

// Each input gets a tracker of its own, so that a video's face ids start at 0
// as on a run of it alone.
FaceTracker MakeTracker(const FaceModels& models, const LandmarksOptions& options) {
  FaceTrackerOptions tracker_options;
  tracker_options.largest_only = options.largest;
  tracker_options.smooth = !options.no_smoothing;
  tracker_options.head_pose = options.head_pose;
  return FaceTracker(models.landmarks, models.mean_face, tracker_options);
}

int RunOnOne(const LandmarksOptions& options, MediaKind kind, FaceTracker& tracker) {
  return kind == MediaKind::kImage ? RunOnImage(options, tracker) : RunOnVideo(options, tracker);
}

// Several inputs, or folders of them: each searched into the folders -o,
// --csv and --overlay name, as a run on it alone searches it, the landmark
// model loaded once. Every input and output is checked before any work.
int RunBatch(const LandmarksOptions& options) {
  options.camera.Check();
  const std::vector<BatchInput> inputs = ExpandBatchInputs(options.batch, {options.output, options.csv, options.overlay});
  const std::vector<AnalysisOutputs> outputs = PlanAnalysisOutputs(inputs, options.output, options.csv, options.overlay);
  const FaceModels models = FaceModels::Load(Assets::Resolve(options.common.assets));
  return RunEachInput(inputs, [&](std::size_t i) {
    FaceTracker tracker = MakeTracker(models, options);
    return RunOnOne(OptionsForInput(options, inputs[i], outputs[i]), inputs[i].kind, tracker);
  });
}

int RunLandmarks(LandmarksOptions options) {
  ApplyLogLevel(options.common);
  if (IsBatch(options.batch.inputs, options.output)) return RunBatch(options);
  options.input = options.batch.inputs.front();
  const MediaKind kind = DetectMediaKind(options.input);
  RequireAnalysisOutputs(options.output, options.csv, options.overlay, kind, options.input);
  FaceTracker tracker = MakeTracker(FaceModels::Load(Assets::Resolve(options.common.assets)), options);
  return RunOnOne(options, kind, tracker);
}

}  // namespace

Command RegisterLandmarksCommand(CLI::App& root) {
  auto options = std::make_shared<LandmarksOptions>();
  CLI::App* app = root.add_subcommand("landmarks", "Find faces, their 68 landmarks and head pose in an image or video");
  AddBatchInputOptions(*app, options->batch);
  app->add_option("-o,--output", options->output,
                  "JSON output: one document for an image, one line per frame for a video; for several inputs a "
                  "folder, where each gets its name.json (.jsonl for a video)")
      ->required();
  app->add_option("--csv", options->csv, "Also write a CSV with OpenFace's column names (several inputs: a folder)");
  app->add_option("--overlay", options->overlay,
                  "Draw the results over the input (.png/.jpg for images, .mp4 for videos; several inputs: a folder)");
  app->add_flag("--largest", options->largest, "Report only the largest face");
  AddHeadPoseOption(*app, options->head_pose);
  app->add_flag("--no-smoothing", options->no_smoothing, "Report raw video landmarks, without temporal smoothing");
  AddCameraOptions(*app, options->camera);
  AddCommonOptions(*app, options->common);
  return {app, [options] { return RunLandmarks(*options); }};
}

}  // namespace gazedirector::cli
