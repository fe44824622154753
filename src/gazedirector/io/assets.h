#pragma once

#include <filesystem>
#include <string>

namespace gazedirector {

// Where the model assets live. One setting decides: --assets DIR, else the
// environment variable GAZEDIRECTOR_ASSETS, else ../shared/assets beside the
// repository. The dlib landmark model comes from Debian's libdlib-data unless
// GAZEDIRECTOR_LANDMARK_MODEL names another file.
class Assets {
 public:
  // Fails with ExitCode::kAssets, saying where to put them, when incomplete.
  static Assets Resolve(const std::string& cli_dir = "");

  const std::filesystem::path& root() const { return root_; }
  std::filesystem::path eye_model() const { return root_ / "eye-model"; }
  std::filesystem::path mean_face() const { return root_ / "face" / "landmarks68_mean3d.json"; }
  const std::filesystem::path& landmark_model() const { return landmark_model_; }

  // A cache folder for data derived from the assets (the texture PCA):
  // $GAZEDIRECTOR_CACHE, else $XDG_CACHE_HOME/gazedirector, else ~/.cache/gazedirector.
  static std::filesystem::path CacheDir();

 private:
  std::filesystem::path root_;
  std::filesystem::path landmark_model_;
};

// The default locations of ../shared/assets and ../shared/data (the real test
// data), fixed at build time; GAZEDIRECTOR_DATA overrides the latter.
std::filesystem::path DefaultAssetsDir();
std::filesystem::path DefaultDataDir();
// The appearance gaze prior (AppearanceGaze) that the build trains with
// `gazedirector train-appearance` on every Columbia crop: models/ in the build tree.
std::filesystem::path DefaultAppearanceModelPath();

}  // namespace gazedirector
