#include "gazedirector/io/assets.h"

#include <cstdlib>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "gazedirector/util/error.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;
using testing::ScopedEnv;

std::string FailureOf(const std::string& cli_dir) {
  try {
    Assets::Resolve(cli_dir);
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ExitCode::kAssets);
    return error.what();
  }
  ADD_FAILURE() << "resolved " << cli_dir;
  return "";
}

// The real assets with one file missing, as a half-copied folder (links to
// the others, so that nothing is copied).
fs::path AssetsWithout(const fs::path& missing) {
  const fs::path real = testing::TestAssets().root();
  const fs::path copy = testing::ScratchDir("assets_without");
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(real)) {
    const fs::path relative = entry.path().lexically_relative(real);
    if (entry.is_directory()) {
      fs::create_directories(copy / relative);
    } else if (relative != missing) {
      fs::create_symlink(entry.path(), copy / relative);
    }
  }
  return copy;
}

TEST(AssetsTest, TheCommandLineFolderComesBeforeTheEnvironment) {
  const fs::path real = testing::TestAssets().root();
  const fs::path nowhere = testing::ScratchDir("assets_nowhere") / "nowhere";
  const ScopedEnv env("GAZEDIRECTOR_ASSETS", nowhere.string());
  EXPECT_EQ(Assets::Resolve(real.string()).root(), fs::weakly_canonical(real));
  EXPECT_EQ(Assets::Resolve(real.string()).eye_model(), fs::weakly_canonical(real) / "eye-model");
  const std::string from_env = FailureOf("");
  EXPECT_NE(from_env.find("(from GAZEDIRECTOR_ASSETS)"), std::string::npos) << from_env;
  EXPECT_NE(from_env.find(nowhere.string()), std::string::npos) << from_env;
}

// A user who copied the assets halfway learns which file is missing, and
// where the assets should go, in one line.
TEST(AssetsTest, AMissingFileIsNamedWithWhereTheAssetsBelong) {
  const fs::path copy = AssetsWithout("eye-model/shape/pca_components.txt");
  const std::string message = FailureOf(copy.string());
  EXPECT_NE(message.find("(from --assets) lacks eye-model/shape/pca_components.txt"), std::string::npos) << message;
  EXPECT_NE(message.find("../shared/assets"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one line";
}

TEST(AssetsTest, AMissingLandmarkModelPointsToItsDebianPackage) {
  const fs::path real = testing::TestAssets().root();
  const ScopedEnv env("GAZEDIRECTOR_LANDMARK_MODEL", (testing::ScratchDir("assets_dlib") / "none.dat").string());
  const std::string message = FailureOf(real.string());
  EXPECT_NE(message.find("libdlib-data"), std::string::npos) << message;
}

TEST(AssetsTest, TheCacheFolderFollowsTheEnvironment) {
  const ScopedEnv home("HOME", "/home/someone");
  {
    const ScopedEnv cache("GAZEDIRECTOR_CACHE", "/tmp/gd-cache");
    const ScopedEnv xdg("XDG_CACHE_HOME", "/tmp/xdg");
    EXPECT_EQ(Assets::CacheDir(), fs::path("/tmp/gd-cache"));
  }
  {
    const ScopedEnv cache("GAZEDIRECTOR_CACHE", std::nullopt);
    const ScopedEnv xdg("XDG_CACHE_HOME", "/tmp/xdg");
    EXPECT_EQ(Assets::CacheDir(), fs::path("/tmp/xdg/gazedirector"));
  }
  {
    const ScopedEnv cache("GAZEDIRECTOR_CACHE", "");
    const ScopedEnv xdg("XDG_CACHE_HOME", std::nullopt);
    EXPECT_EQ(Assets::CacheDir(), fs::path("/home/someone/.cache/gazedirector")) << "an empty setting counts as none";
  }
}

}  // namespace
}  // namespace gazedirector
