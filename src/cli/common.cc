#include "cli/common.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include "gazedirector/io/atomic_output.h"
#include "gazedirector/io/media.h"
#include "gazedirector/util/error.h"

namespace gazedirector::cli {

namespace {
bool log_lines_name_their_input = false;
}  // namespace

void SetLogPrefix(const std::string& prefix) {
  std::string literal;  // '%' starts a field in spdlog's patterns
  for (const char c : prefix) literal += c == '%' ? std::string("%%") : std::string(1, c);
  spdlog::set_pattern("%^%l%$: " + literal + "%v");
}

ScopedLogPrefix::ScopedLogPrefix(const std::string& prefix) {
  SetLogPrefix(prefix);
  log_lines_name_their_input = true;
}

ScopedLogPrefix::~ScopedLogPrefix() {
  SetLogPrefix("");
  log_lines_name_their_input = false;
}

std::string LogLabel(const std::string& input) { return log_lines_name_their_input ? std::string() : input + ": "; }

FaceModels FaceModels::Load(const Assets& assets) {
  return {LandmarkDetector::Load(assets.landmark_model(), Assets::CacheDir()), LoadMeanFace(assets.mean_face())};
}

void AddCommonOptions(CLI::App& command, CommonOptions& options) {
  command.add_option("--assets", options.assets,
                     "Model asset folder (default: $GAZEDIRECTOR_ASSETS, else ../shared/assets beside the repository)");
  command.add_flag("-q,--quiet", options.quiet, "Print only warnings and errors");
  command.add_flag("-v,--verbose", options.verbose, "Print debugging detail");
}

void ApplyLogLevel(const CommonOptions& options) {
  spdlog::set_level(options.quiet ? spdlog::level::warn : options.verbose ? spdlog::level::debug : spdlog::level::info);
}

Camera CameraOptions::Resolve(int width, int height) const {
  Camera camera = Camera::Default(width, height);
  if (fx) camera.fx = *fx, camera.fy = fy.value_or(*fx);
  if (fy) camera.fy = *fy, camera.fx = fx.value_or(*fy);
  if (cx) camera.cx = *cx;
  if (cy) camera.cy = *cy;
  if (!(camera.fx > 0 && camera.fy > 0 && std::isfinite(camera.fx) && std::isfinite(camera.fy))) {
    Fail(ExitCode::kUsage, "--fx {} --fy {}: focal lengths must be positive numbers of pixels", camera.fx, camera.fy);
  }
  if (!std::isfinite(camera.cx) || !std::isfinite(camera.cy)) {
    Fail(ExitCode::kUsage, "--cx {} --cy {}: the principal point must be numbers of pixels", camera.cx, camera.cy);
  }
  return camera;
}

void AddCameraOptions(CLI::App& command, CameraOptions& options) {
  const char* group = "Camera (default: fx = fy = max(width, height), principal point at the centre)";
  command.add_option("--fx", options.fx, "Focal length in pixels along x")->group(group);
  command.add_option("--fy", options.fy, "Focal length in pixels along y (default: fx)")->group(group);
  command.add_option("--cx", options.cx, "Principal point x in pixels")->group(group);
  command.add_option("--cy", options.cy, "Principal point y in pixels")->group(group);
}

void AddHeadPoseOption(CLI::App& command, HeadPoseMethod& method) {
  // The enum's values by name; CLI11 then reads the number into the enum.
  const CLI::Validator by_name(
      [](std::string& value) -> std::string {
        const std::string name = CLI::detail::to_lower(value);
        if (name == "pnp") value = std::to_string(static_cast<int>(HeadPoseMethod::kPerspectiveNPoint));
        else if (name == "kabsch") value = std::to_string(static_cast<int>(HeadPoseMethod::kKabsch));
        else return "expected pnp or kabsch, got '" + value + "'";
        return "";
      },
      "");
  command
      .add_option("--head-pose", method,
                  "How the mean 3D face is aligned to the landmarks: pnp (perspective-n-point, in pixels) or kabsch "
                  "(the paper's Kabsch alignment, the landmarks lifted onto their lines of sight)")
      ->transform(by_name)
      ->option_text("TEXT:{pnp,kabsch}=pnp");
}

void RequireExtension(const std::filesystem::path& path, const std::string& option, const std::vector<std::string>& allowed) {
  const std::string extension = LowerExtension(path);
  if (std::find(allowed.begin(), allowed.end(), extension) == allowed.end()) {
    Fail(ExitCode::kUsage, "{} {}: expected a file ending in {}", option, path.string(), fmt::join(allowed, ", "));
  }
}

namespace {

const std::vector<std::string> kImageExtensions = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".webp", ".bmp"};

}  // namespace

bool IsImagePath(const std::filesystem::path& path) {
  return std::find(kImageExtensions.begin(), kImageExtensions.end(), LowerExtension(path)) != kImageExtensions.end();
}

void RequireOutputKind(const std::string& path, const std::string& option, MediaKind kind, const std::string& input) {
  if (path.empty()) return;
  if (kind == MediaKind::kImage && !IsImagePath(path)) {
    Fail(ExitCode::kUsage, "{} {}: an image's output is an image ({})", option, path, fmt::join(kImageExtensions, ", "));
  }
  if (kind == MediaKind::kVideo && !HasVideoExtension(path)) {
    Fail(ExitCode::kUsage, "{} {}: a video's output is a video ({})", option, path, fmt::join(VideoExtensions(), ", "));
  }
  RequireWritable(path, {input});
}

void RequireAnalysisOutputs(const std::string& output, const std::string& csv, const std::string& overlay,
                            MediaKind kind, const std::string& input) {
  RequireExtension(output, "-o", {".json", ".jsonl"});
  RequireCsvOutput(csv, {input});
  RequireOutputKind(overlay, "--overlay", kind, input);
  RequireWritable(output, {input});
}

void RequireCsvOutput(const std::string& csv, const std::vector<std::filesystem::path>& inputs) {
  if (csv.empty()) return;
  RequireExtension(csv, "--csv", {".csv"});
  RequireWritable(csv, inputs);
}

void RequireImageOutput(const std::string& path, const std::string& option) {
  if (path.empty()) return;
  if (!IsImagePath(path)) {
    Fail(ExitCode::kUsage, "{} {}: expected an image file ({})", option, path, fmt::join(kImageExtensions, ", "));
  }
  RequireWritable(path);
}

void RequireWritableFolder(const std::string& dir, const std::string& option) {
  if (dir.empty()) return;
  std::error_code ec;
  if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec)) {
    Fail(ExitCode::kOutput, "{} {}: not a folder", option, dir);
  }
  RequireWritable(std::filesystem::path(dir) / "probe");
}

void WarnIfTruncated(const VideoReader& reader, const std::string& input) {
  if (reader.EndedEarly()) {
    spdlog::warn("{}: the video ended after {} of {} frames (truncated?)", input, reader.frame_index() + 1,
                 reader.info().frame_count);
  }
}

}  // namespace gazedirector::cli
