// gazedirector render: the eye-region model, alone or placed over a real face.
#include <algorithm>
#include <fstream>
#include <memory>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "cli/common.h"
#include "gazedirector/face/face_tracker.h"
#include "gazedirector/fit/initialization.h"
#include "gazedirector/geometry/rotation.h"
#include "gazedirector/io/assets.h"
#include "gazedirector/io/image_io.h"
#include "gazedirector/io/json_format.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/render/renderer.h"
#include "gazedirector/util/error.h"

namespace gazedirector::cli {
namespace {

struct RenderOptions {
  CommonOptions common;
  CameraOptions camera;
  std::string params;
  std::string size = "400x200";
  std::string output;
  std::string overlay;
  std::string buffers_dir;
  std::vector<double> gaze;
  std::optional<double> eyelid;
};

Parameters ReadParameters(const std::string& path) {
  std::ifstream stream(path);
  if (!stream) Fail(ExitCode::kBadInput, "{}: cannot read", path);
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(stream);
  } catch (const nlohmann::json::exception& e) {
    Fail(ExitCode::kBadInput, "{}: invalid JSON ({})", path, JsonErrorText(e));
  }
  // Either Φ itself or a record that holds it under "parameters".
  if (json.is_object() && json.contains("parameters")) json = json["parameters"];
  return Parameters::FromJson(json);
}

cv::Size ParseSize(const std::string& text) {
  int width = 0, height = 0;
  char x = 0;
  std::istringstream stream(text);
  if (!(stream >> width >> x >> height) || x != 'x' || width < 16 || height < 16 || width > 8192 || height > 8192) {
    Fail(ExitCode::kUsage, "--size {}: expected WIDTHxHEIGHT between 16 and 8192", text);
  }
  return {width, height};
}

int RunRender(const RenderOptions& options) {
  ApplyLogLevel(options.common);
  RequireImageOutput(options.output, "-o");
  RequireWritableFolder(options.buffers_dir, "--buffers");
  if (!std::all_of(options.gaze.begin(), options.gaze.end(), WithinQuarterTurn)) {
    Fail(ExitCode::kUsage, "--gaze {},{}: degrees within -90 to 90", options.gaze[0], options.gaze[1]);
  }
  if (options.eyelid && !WithinQuarterTurn(*options.eyelid)) {
    Fail(ExitCode::kUsage, "--eyelid {}: degrees within -90 to 90", *options.eyelid);
  }
  const Assets assets = Assets::Resolve(options.common.assets);
  const auto model = EyeRegionModel::Load(assets);

  Parameters phi = options.params.empty() ? Parameters() : ReadParameters(options.params);
  cv::Mat background;
  Camera camera;
  std::vector<std::filesystem::path> inputs;
  if (!options.overlay.empty()) {
    background = ReadImage(options.overlay);
    inputs.push_back(options.overlay);
    camera = options.camera.Resolve(background.cols, background.rows);
    if (options.params.empty()) {
      FaceTrackerOptions tracker_options;
      tracker_options.largest_only = true;
      FaceTracker tracker(LandmarkDetector::Load(assets.landmark_model(), Assets::CacheDir()),
                          LoadMeanFace(assets.mean_face()), tracker_options);
      const std::vector<Face> faces = tracker.DetectFaces(background, camera);
      if (faces.empty()) Fail(ExitCode::kNoFace, "no face found in {} to place the model on", options.overlay);
      phi = InitializeFromLandmarks(faces[0], camera, *model);
    }
  } else {
    const cv::Size size = ParseSize(options.size);
    camera = options.camera.Resolve(size.width, size.height);
    if (options.params.empty()) {
      // A long lens framing both eye regions (about 150 mm across).
      if (!options.camera.fx) camera.fx = camera.fy = 3.0 * std::max(size.width, size.height);
      phi.block<Block::kTranslation>() = Eigen::Vector3d(0, 0, camera.fx * 150.0 / size.width);
    }
  }
  if (options.gaze.size() == 2) phi.gaze_pitch() = options.gaze[0], phi.gaze_yaw() = options.gaze[1];
  if (options.eyelid) phi.eyelid_pitch() = *options.eyelid;

  Renderer renderer(model);
  RenderBuffers buffers;
  renderer.Render(phi, camera, buffers);
  WriteImage(options.output, buffers.ColourImage(background), inputs);
  if (!options.buffers_dir.empty()) {
    const std::filesystem::path dir(options.buffers_dir);
    WriteImage(dir / "mask.png", buffers.MaskImage(), inputs);
    cv::Mat parts = buffers.PartImage();
    cv::Mat coloured(parts.size(), CV_8UC3, cv::Scalar::all(0));
    const cv::Vec3b colours[4] = {{60, 160, 230}, {60, 230, 160}, {230, 120, 60}, {230, 60, 200}};
    for (int i = 0; i < parts.rows * parts.cols; ++i) {
      if (parts.data[i] < 4) coloured.at<cv::Vec3b>(i / parts.cols, i % parts.cols) = colours[parts.data[i]];
    }
    WriteImage(dir / "parts.png", coloured, inputs);
  }
  spdlog::info("rendered {}x{} ({} model pixels) -> {}", camera.width, camera.height, buffers.foreground.size(), options.output);
  return 0;
}

}  // namespace

Command RegisterRenderCommand(CLI::App& root) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* app = root.add_subcommand("render", "Render the eye-region model, alone or over a real face");
  app->add_option("-o,--output", options->output, "Output image")->required();
  app->add_option("--params", options->params, "Model parameters Φ (JSON); default: the mean model looking at the camera");
  CLI::Option* size =
      app->add_option("--size", options->size, "Image size WIDTHxHEIGHT without --overlay")->capture_default_str();
  // Over a photo the image is the photo's size.
  app->add_option("--overlay", options->overlay, "Draw the model over this photo, placed from its face's landmarks")
      ->excludes(size);
  app->add_option("--gaze", options->gaze, "Gaze pitch,yaw in degrees (head frame; up and toward the subject's left are +)")
      ->expected(2)->delimiter(',');
  app->add_option("--eyelid", options->eyelid, "Eyelid pitch in degrees (up +)");
  app->add_option("--buffers", options->buffers_dir, "Also write the foreground mask and part ids here");
  AddCameraOptions(*app, options->camera);
  AddCommonOptions(*app, options->common);
  return {app, [options] { return RunRender(*options); }};
}

}  // namespace gazedirector::cli
