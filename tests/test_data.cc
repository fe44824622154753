#include "tests/test_data.h"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include "gazedirector/eval/columbia.h"
#include "gazedirector/io/image_io.h"

namespace gazedirector::testing {
namespace fs = std::filesystem;

fs::path SharedDir() { return fs::path(GAZEDIRECTOR_SHARED_DIR); }

fs::path DataPath(const std::string& relative) { return SharedDir() / "data" / relative; }

const Assets& TestAssets() {
  static const Assets assets = Assets::Resolve((SharedDir() / "assets").string());
  return assets;
}

std::shared_ptr<const LandmarkDetector> SharedLandmarkDetector() {
  static const auto detector = LandmarkDetector::Load(TestAssets().landmark_model(), Assets::CacheDir());
  return detector;
}

std::shared_ptr<const EyeRegionModel> SharedModel() {
  static const auto model = EyeRegionModel::Load(TestAssets());
  return model;
}

const AppearanceGazeTrainer& ColumbiaAppearanceTrainer() {
  static const AppearanceGazeTrainer trainer = [] {
    AppearanceGazeTrainer trained;
    AddColumbiaCrops(ListColumbia(DataPath("columbia-eyes")), trained);
    return trained;
  }();
  return trainer;
}

const MeanFace& SharedMeanFace() {
  static const MeanFace mean_face = LoadMeanFace(TestAssets().mean_face());
  return mean_face;
}

FaceTracker MakeFaceTracker(const FaceTrackerOptions& options) {
  return FaceTracker(SharedLandmarkDetector(), SharedMeanFace(), options);
}

DetectedStill DetectStill(const std::string& photo) {
  DetectedStill still;
  still.image = ReadImage(DataPath(photo));
  still.camera = Camera::Default(still.image.cols, still.image.rows);
  still.faces = MakeFaceTracker().DetectFaces(still.image, still.camera);
  return still;
}

const FittedStill& FitStill(const std::string& photo) {
  static std::mutex mutex;
  static std::map<std::string, FittedStill> fitted;
  const std::lock_guard<std::mutex> lock(mutex);
  const auto found = fitted.find(photo);
  if (found != fitted.end()) return found->second;
  FittedStill still{DetectStill(photo), {}};
  if (!still.faces.empty()) still.fit = Fitter(SharedModel()).FitFace(still.image, still.camera, still.faces.front());
  return fitted.emplace(photo, std::move(still)).first->second;
}

cv::Mat GrayPhoto(const std::string& photo) {
  cv::Mat gray;
  cv::cvtColor(ReadImage(DataPath(photo)), gray, cv::COLOR_BGR2GRAY);
  return gray;
}

Eigen::Vector2d TurnedPhoto::Map(const Eigen::Vector2d& p) const {
  return {map(0, 0) * p.x() + map(0, 1) * p.y() + map(0, 2), map(1, 0) * p.x() + map(1, 1) * p.y() + map(1, 2)};
}

Landmarks68 TurnedPhoto::Map(const Landmarks68& landmarks) const {
  Landmarks68 mapped;
  for (int i = 0; i < kNumLandmarks; ++i) mapped[i] = Map(landmarks[i]);
  return mapped;
}

TurnedPhoto TurnPhoto(const cv::Mat& image, double degrees) {
  const cv::Point2f centre(0.5f * (image.cols - 1), 0.5f * (image.rows - 1));
  cv::Mat map = cv::getRotationMatrix2D(centre, -degrees, 1.0);  // OpenCV turns counter-clockwise
  const cv::Rect2f bounds = cv::RotatedRect(centre, image.size(), static_cast<float>(degrees)).boundingRect2f();
  map.at<double>(0, 2) += 0.5 * bounds.width - centre.x;
  map.at<double>(1, 2) += 0.5 * bounds.height - centre.y;
  TurnedPhoto turned;
  turned.map = cv::Matx23d(map);
  cv::warpAffine(image, turned.image, map, cv::Size(static_cast<int>(std::ceil(bounds.width)), static_cast<int>(std::ceil(bounds.height))));
  return turned;
}

std::string ReadText(const fs::path& path) {
  std::ifstream stream(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(stream), {});
}

void WritePrefix(const fs::path& from, const fs::path& to, std::size_t bytes) {
  std::ofstream(to, std::ios::binary) << ReadText(from).substr(0, bytes);
}

fs::path ScratchDir(const std::string& name) {
  static const fs::path root = fs::temp_directory_path() / ("gazedirector-tests-" + std::to_string(::getpid()));
  static const struct Cleanup {
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(root, ec);
    }
  } cleanup;
  const fs::path dir = root / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

fs::path CliPath() { return fs::path(GAZEDIRECTOR_CLI_PATH); }

int RunCommand(const std::string& command, std::string* output) {
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return -1;
  std::array<char, 4096> buffer;
  std::string text;
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) text += buffer.data();
  const int status = ::pclose(pipe);
  if (output != nullptr) *output = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int RunCli(const std::string& arguments, std::string* output) {
  return RunCommand(fmt::format("'{}' {}", CliPath().string(), arguments), output);
}

std::string Quote(const fs::path& path) { return fmt::format("'{}'", path.string()); }

int WriteSelectedFrames(const std::string& video, double seconds, const std::string& select, const fs::path& out,
                        bool audio) {
  std::string escaped;  // commas separate filters unless escaped
  for (const char c : select) escaped += c == ',' ? std::string("\\,") : std::string(1, c);
  return RunCommand(fmt::format("ffmpeg -v error -y -i {} -t {} {} -vf \"select='{}'\" -vsync vfr {}", Quote(DataPath(video)),
                                seconds, audio ? "" : "-an", escaped, Quote(out)));
}

bool NoPartialFiles(const fs::path& dir) {
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.path().filename().string().find(".partial") != std::string::npos) return false;
  }
  return true;
}

ScopedEnv::ScopedEnv(const char* name, const std::optional<std::string>& value) : name_(name) {
  if (const char* old = std::getenv(name)) old_ = old;
  if (value) {
    ::setenv(name, value->c_str(), 1);
  } else {
    ::unsetenv(name);
  }
}

ScopedEnv::~ScopedEnv() {
  if (old_) {
    ::setenv(name_, old_->c_str(), 1);
  } else {
    ::unsetenv(name_);
  }
}

CapturedLog::CapturedLog() : previous_(spdlog::default_logger()) {
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(text_);
  sink->set_pattern("%v");
  auto logger = std::make_shared<spdlog::logger>("captured", sink);
  logger->set_level(spdlog::level::info);
  spdlog::set_default_logger(logger);
}

CapturedLog::~CapturedLog() { spdlog::set_default_logger(previous_); }

}  // namespace gazedirector::testing
