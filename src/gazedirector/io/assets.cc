#include "gazedirector/io/assets.h"

#include <array>
#include <cstdlib>

#include "gazedirector/util/error.h"
#include "gazedirector/util/temporary_folder.h"

#if !defined(GAZEDIRECTOR_SOURCE_DIR) || !defined(GAZEDIRECTOR_BINARY_DIR)
#error "GAZEDIRECTOR_SOURCE_DIR and GAZEDIRECTOR_BINARY_DIR must be defined by the build"
#endif

namespace gazedirector {
namespace fs = std::filesystem;
namespace {

constexpr std::array<const char*, 8> kRequiredFiles = {
    "eye-model/mesh/eye_region.obj",         "eye-model/mesh/eyeball.obj",
    "eye-model/shape/mesh_mean.txt",         "eye-model/shape/pca_components.txt",
    "eye-model/shape/transformed_std.txt",   "eye-model/subdivision/new_v_idxs_eye_region.txt",
    "eye-model/textures/iris/eyeball_brown.png", "face/landmarks68_mean3d.json"};

const char* GetEnv(const char* name) {
  const char* value = std::getenv(name);
  return value != nullptr && value[0] != '\0' ? value : nullptr;
}

}  // namespace

fs::path DefaultAssetsDir() { return (fs::path(GAZEDIRECTOR_SOURCE_DIR) / ".." / "shared" / "assets").lexically_normal(); }

fs::path DefaultAppearanceModelPath() {
  return (fs::path(GAZEDIRECTOR_BINARY_DIR) / "models" / "appearance_gaze.cbor").lexically_normal();
}

fs::path DefaultDataDir() {
  if (const char* dir = GetEnv("GAZEDIRECTOR_DATA")) return dir;
  return (fs::path(GAZEDIRECTOR_SOURCE_DIR) / ".." / "shared" / "data").lexically_normal();
}

Assets Assets::Resolve(const std::string& cli_dir) {
  Assets assets;
  std::string origin;
  if (!cli_dir.empty()) {
    assets.root_ = cli_dir;
    origin = "--assets";
  } else if (const char* env = GetEnv("GAZEDIRECTOR_ASSETS")) {
    assets.root_ = env;
    origin = "GAZEDIRECTOR_ASSETS";
  } else {
    assets.root_ = DefaultAssetsDir();
    origin = "the default location";
  }
  std::error_code ec;
  assets.root_ = fs::weakly_canonical(assets.root_, ec);
  for (const char* file : kRequiredFiles) {
    if (!fs::is_regular_file(assets.root_ / file, ec)) {
      Fail(ExitCode::kAssets,
           "model assets not found: {} (from {}) lacks {}; put the GazeDirector assets folder at "
           "../shared/assets beside the repository, or pass --assets DIR, or set GAZEDIRECTOR_ASSETS",
           assets.root_.string(), origin, file);
    }
  }
  const char* model = GetEnv("GAZEDIRECTOR_LANDMARK_MODEL");
  assets.landmark_model_ = model ? fs::path(model) : fs::path("/usr/share/dlib/shape_predictor_68_face_landmarks.dat");
  if (!fs::is_regular_file(assets.landmark_model_, ec)) {
    Fail(ExitCode::kAssets,
         "the dlib 68-point landmark model {} is missing; install Debian's libdlib-data "
         "(bash scripts/setup.sh does) or set GAZEDIRECTOR_LANDMARK_MODEL",
         assets.landmark_model_.string());
  }
  return assets;
}

fs::path Assets::CacheDir() {
  if (const char* dir = GetEnv("GAZEDIRECTOR_CACHE")) return dir;
  if (const char* xdg = GetEnv("XDG_CACHE_HOME")) return fs::path(xdg) / "gazedirector";
  if (const char* home = GetEnv("HOME")) return fs::path(home) / ".cache" / "gazedirector";
  return TemporaryFolder() / "gazedirector-cache";
}

}  // namespace gazedirector
