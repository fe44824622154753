#include "gazedirector/model/skin_texture_model.h"

#include <cmath>

#include <gtest/gtest.h>

#include "gazedirector/util/statistics.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;

TEST(SkinTextureModelTest, BuildsCachesAndReloadsTheSamePca) {
  const fs::path skin = testing::TestAssets().eye_model() / "textures" / "skin";
  const fs::path cache = testing::ScratchDir("skin_cache");
  const SkinTextureModel built = SkinTextureModel::LoadOrBuild(skin, cache, 8);
  ASSERT_FALSE(fs::is_empty(cache)) << "the PCA is cached";
  const SkinTextureModel loaded = SkinTextureModel::LoadOrBuild(skin, cache, 8);
  ASSERT_EQ(built.num_modes(), 8);
  ASSERT_EQ(built.num_subjects(), 20);
  for (int j = 0; j < 8; ++j) EXPECT_EQ(built.stddev(j), loaded.stddev(j));
  const std::size_t n = static_cast<std::size_t>(SkinTextureModel::kSize) * SkinTextureModel::kSize * 3;
  for (std::size_t t = 0; t < n; t += 997) ASSERT_EQ(built.mean(SkinTextureModel::kAhead)[t], loaded.mean(SkinTextureModel::kAhead)[t]);

  // Coefficients are in standard deviations: over the 20 subjects each mode
  // has unit spread, and the variances fall from mode to mode.
  for (int j = 0; j < 8; ++j) {
    std::vector<double> squares;
    for (int i = 0; i < 20; ++i) squares.push_back(std::pow(built.subject_coefficients(i)[j], 2));
    EXPECT_NEAR(Mean(squares) * 20 / 19, 1.0, 1e-3) << "mode " << j;
    if (j > 0) {
      EXPECT_LE(built.stddev(j), built.stddev(j - 1));
    }
  }
}

TEST(SkinTextureModelTest, EightModesExplainMostOfEachSubjectsSkin) {
  const fs::path skin = testing::TestAssets().eye_model() / "textures" / "skin";
  const SkinTextureModel model = SkinTextureModel::LoadOrBuild(skin, Assets::CacheDir(), 8);
  const std::size_t texels = static_cast<std::size_t>(SkinTextureModel::kSize) * SkinTextureModel::kSize;
  double mean_error = 0, model_error = 0;
  for (int i = 0; i < model.num_subjects(); ++i) {
    const std::vector<float> truth = SkinTextureModel::LoadSkinMap(skin / (model.subject_names()[i] + "_color.png"), SkinTextureModel::kSize);
    RgbaTexture ahead, down;
    model.Compose(model.subject_coefficients(i).data(), ahead, down);
    for (std::size_t t = 0; t < texels; ++t) {
      if (model.footprint()[t] == 0) continue;
      for (int c = 0; c < 3; ++c) {
        mean_error += std::abs(truth[3 * t + c] - model.mean(SkinTextureModel::kAhead)[3 * t + c]);
        model_error += std::abs(truth[3 * t + c] - ahead.data()[4 * t + c]);
      }
    }
  }
  EXPECT_LT(model_error, 0.4 * mean_error);  // measured: 0.30
}

}  // namespace
}  // namespace gazedirector
