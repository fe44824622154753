#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <spdlog/logger.h>

#include "gazedirector/face/face_tracker.h"
#include "gazedirector/face/landmark_detector.h"
#include "gazedirector/face/mean_face.h"
#include "gazedirector/fit/appearance_gaze.h"
#include "gazedirector/fit/fitter.h"
#include "gazedirector/io/assets.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/util/error.h"

namespace gazedirector::testing {

// The real data beside the repository (../shared), as the build found it.
std::filesystem::path SharedDir();
std::filesystem::path DataPath(const std::string& relative);  // under ../shared/data
const Assets& TestAssets();
// One landmark model per test binary: loading it takes half a second.
std::shared_ptr<const LandmarkDetector> SharedLandmarkDetector();
// The eye-region model, loaded once per test binary.
std::shared_ptr<const EyeRegionModel> SharedModel();
// The assets' 3D mean face, read once per test binary.
const MeanFace& SharedMeanFace();
// Every Columbia crop (all head poses, as train-appearance trains) added to
// an appearance gaze trainer, read once per test binary; its Solve(subject)
// gives a model that has not seen that subject.
const AppearanceGazeTrainer& ColumbiaAppearanceTrainer();
// A fresh face tracker on the shared landmark model and the assets' mean face.
FaceTracker MakeFaceTracker(const FaceTrackerOptions& options = {});

// A real still under ../shared/data, its default camera, and the faces a
// fresh face tracker finds there.
struct DetectedStill {
  cv::Mat image;
  Camera camera;
  std::vector<Face> faces;
};
DetectedStill DetectStill(const std::string& photo);
// The same with its first face fitted afresh with the default options; each
// photo is detected and fitted once per test binary.
struct FittedStill : DetectedStill {
  FitResult fit;
};
const FittedStill& FitStill(const std::string& photo);
// A real photo under ../shared/data as 8-bit grey, as the face searches take it.
cv::Mat GrayPhoto(const std::string& photo);
// A photo turned by `degrees` clockwise as shown about its centre, on a
// canvas that holds all of it (OpenCV's own rotation, black outside), and the
// map of its points: a face tilted in the image by as much.
struct TurnedPhoto {
  cv::Mat image;
  cv::Matx23d map;
  Eigen::Vector2d Map(const Eigen::Vector2d& p) const;
  Landmarks68 Map(const Landmarks68& landmarks) const;
};
TurnedPhoto TurnPhoto(const cv::Mat& image, double degrees);

// A file's bytes.
std::string ReadText(const std::filesystem::path& path);
// Writes the first `bytes` bytes of `from` to `to`: a file cut short.
void WritePrefix(const std::filesystem::path& from, const std::filesystem::path& to, std::size_t bytes);

// The exit code of the error `action` fails with (kOk when it does not), and
// a test failure when that error's message is more than one line.
template <typename Action>
ExitCode ExitCodeOf(Action&& action) {
  try {
    action();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "messages are one line: " << e.what();
    return e.code();
  }
  return ExitCode::kOk;
}

// A fresh folder under the build tree's temp dir, removed with the process.
std::filesystem::path ScratchDir(const std::string& name);
// The gazedirector program built beside the tests.
std::filesystem::path CliPath();

// Runs a shell command; returns its exit code and fills `output` with
// stdout+stderr.
int RunCommand(const std::string& command, std::string* output = nullptr);
// Runs the CLI with `arguments` (shell-quoted by the caller), as RunCommand.
int RunCli(const std::string& arguments, std::string* output = nullptr);
// A path in single quotes, for RunCli's shell.
std::string Quote(const std::filesystem::path& path);
// Writes the frames of a real video under ../shared/data that ffmpeg's
// `select` expression keeps, over its first `seconds`, each at its own time
// (a variable-rate clip, as phones and screen recorders write); its audio is
// kept when `audio`. Returns ffmpeg's exit status.
int WriteSelectedFrames(const std::string& video, double seconds, const std::string& select,
                        const std::filesystem::path& out, bool audio = false);
// True when no temporary ".partial" file is left anywhere under `dir`.
bool NoPartialFiles(const std::filesystem::path& dir);

// Sets an environment variable for one scope, then puts back what was there.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::optional<std::string>& value);
  ~ScopedEnv();
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// Routes the log (info and above, messages only) into a string for one scope.
class CapturedLog {
 public:
  CapturedLog();
  ~CapturedLog();
  CapturedLog(const CapturedLog&) = delete;
  CapturedLog& operator=(const CapturedLog&) = delete;
  std::string text() const { return text_.str(); }

 private:
  std::ostringstream text_;
  std::shared_ptr<spdlog::logger> previous_;
};

}  // namespace gazedirector::testing
