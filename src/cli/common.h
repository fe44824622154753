#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "gazedirector/face/head_pose.h"
#include "gazedirector/face/landmark_detector.h"
#include "gazedirector/face/mean_face.h"
#include "gazedirector/geometry/camera.h"
#include "gazedirector/io/assets.h"
#include "gazedirector/io/media.h"
#include "gazedirector/io/video_reader.h"

namespace gazedirector::cli {

// Log lines read "warning: <prefix>message" (main.cc sets an empty prefix).
void SetLogPrefix(const std::string& prefix);

// While it lives, every log line names what it is about after its level
// ("warning: [2/5] d30.jpg: ..."): one input of several.
class ScopedLogPrefix {
 public:
  explicit ScopedLogPrefix(const std::string& prefix);
  ~ScopedLogPrefix();
  ScopedLogPrefix(const ScopedLogPrefix&) = delete;
  ScopedLogPrefix& operator=(const ScopedLogPrefix&) = delete;
};

// "photo.jpg: " to start a log line about `input`, or nothing while a
// ScopedLogPrefix names it already.
std::string LogLabel(const std::string& input);

// What a face tracker needs (landmarks, track, redirect), loaded once.
struct FaceModels {
  std::shared_ptr<const LandmarkDetector> landmarks;
  MeanFace mean_face;

  static FaceModels Load(const Assets& assets);
};

// Options every subcommand takes.
struct CommonOptions {
  std::string assets;
  bool quiet = false;
  bool verbose = false;
};
void AddCommonOptions(CLI::App& command, CommonOptions& options);
// Applies --quiet / --verbose to the logger.
void ApplyLogLevel(const CommonOptions& options);

// Camera intrinsics: given in full, in part, or by default from the image size.
struct CameraOptions {
  std::optional<double> fx, fy, cx, cy;
  Camera Resolve(int width, int height) const;
  // Fails with a usage error where the values given are no camera's,
  // whatever the image's size: a batch checks them before any work.
  void Check() const { Resolve(1, 1); }
};
void AddCameraOptions(CLI::App& command, CameraOptions& options);

// --head-pose pnp|kabsch: how the mean face is aligned to the landmarks.
void AddHeadPoseOption(CLI::App& command, HeadPoseMethod& method);

// A subcommand: its parser and what runs when it was chosen; run returns the
// process exit code.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

Command RegisterLandmarksCommand(CLI::App& root);
Command RegisterBenchCommand(CLI::App& root);
Command RegisterEvalCommand(CLI::App& root);
Command RegisterRenderCommand(CLI::App& root);
Command RegisterTrackCommand(CLI::App& root);
Command RegisterRedirectCommand(CLI::App& root);
Command RegisterTrainCommand(CLI::App& root);

// Fails with a usage error unless `path`'s extension is one of `allowed`.
void RequireExtension(const std::filesystem::path& path, const std::string& option,
                      const std::vector<std::string>& allowed);
bool IsImagePath(const std::filesystem::path& path);
// Fails with a usage error unless `path` (given as `option`) suits the input's
// kind: an image for an image, a video for a video, and with an output error
// when it is the input itself or cannot be written. Empty paths pass.
void RequireOutputKind(const std::string& path, const std::string& option, MediaKind kind, const std::string& input);
// The outputs of the analysis commands (landmarks, track): -o JSON or JSON
// lines, --csv a CSV, --overlay of the input's kind (optional ones may be
// empty), none of them the input, each writable.
void RequireAnalysisOutputs(const std::string& output, const std::string& csv, const std::string& overlay,
                            MediaKind kind, const std::string& input);
// Fails unless --csv, when given, is a .csv file that can be written and is
// none of `inputs`.
void RequireCsvOutput(const std::string& csv, const std::vector<std::filesystem::path>& inputs = {});
// Fails unless `path` (given as `option`) names an image file (.png, .jpg, ...)
// that can be written. An empty path passes.
void RequireImageOutput(const std::string& path, const std::string& option);
// Fails unless new files can be written in the folder `dir` (created when
// missing). An empty path passes.
void RequireWritableFolder(const std::string& dir, const std::string& option);
// Warns when a video stopped before the frame count its container announced.
void WarnIfTruncated(const VideoReader& reader, const std::string& input);

}  // namespace gazedirector::cli
