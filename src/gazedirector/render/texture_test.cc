#include "gazedirector/render/texture.h"

#include <array>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace gazedirector {
namespace {

// An 8x8 texture whose red channel is the texel's column and green its row
// (counted from the top), so that bilinear samples read back positions.
RgbaTexture Ramp() {
  RgbaTexture texture(8);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      float* texel = texture.data() + (y * 8 + x) * 4;
      texel[0] = static_cast<float>(x), texel[1] = static_cast<float>(y), texel[2] = 1.0f, texel[3] = 0.5f;
    }
  }
  return texture;
}

TEST(TextureTest, SamplesInterpolateBilinearlyBetweenTexelCentres) {
  const RgbaTexture texture = Ramp();
  const RgbaTexture::Level level = texture.level(0);
  // Texel centres sit at (i + 0.5) / 8; v counts up from the bottom.
  const Eigen::Vector4f centre = level.Sample(2.5f / 8, 1.0f - 5.5f / 8);
  EXPECT_NEAR(centre[0], 2.0f, 1e-5);
  EXPECT_NEAR(centre[1], 5.0f, 1e-5);
  const Eigen::Vector4f between = level.Sample(3.25f / 8, 1.0f - 1.75f / 8);
  EXPECT_NEAR(between[0], 2.75f, 1e-5);
  EXPECT_NEAR(between[1], 1.25f, 1e-5);
  EXPECT_NEAR(between[3], 0.5f, 1e-6);
}

TEST(TextureTest, CoordinatesOutsideClampToTheEdgeAndNaNReadsInside) {
  const RgbaTexture texture = Ramp();
  const RgbaTexture::Level level = texture.level(0);
  const Eigen::Vector4f far = level.Sample(5.0f, -3.0f);
  EXPECT_NEAR(far[0], 7.0f, 0.01f);
  EXPECT_NEAR(far[1], 7.0f, 0.01f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const Eigen::Vector4f undefined = level.Sample(nan, nan);
  EXPECT_TRUE(undefined.allFinite());
  EXPECT_EQ(undefined[0], 0.0f);
}

TEST(TextureTest, LocatingManyCoordinatesAgreesWithOneAtATime) {
  const RgbaTexture texture = Ramp();
  const RgbaTexture::Level level = texture.level(0);
  constexpr int kCount = 37;  // not a multiple of any vector width
  std::array<float, kCount> u, v, fx, fy;
  std::array<int32_t, kCount> offset;
  for (int i = 0; i < kCount; ++i) u[i] = -0.2f + 0.037f * i, v[i] = 1.1f - 0.031f * i;
  level.LocateMany(u.data(), v.data(), kCount, offset.data(), fx.data(), fy.data());
  for (int i = 0; i < kCount; ++i) {
    int32_t one_offset;
    float one_fx, one_fy;
    level.Locate(u[i], v[i], one_offset, one_fx, one_fy);
    EXPECT_EQ(offset[i], one_offset) << i;
    EXPECT_FLOAT_EQ(fx[i], one_fx) << i;
    EXPECT_FLOAT_EQ(fy[i], one_fy) << i;
    EXPECT_EQ(level.SampleAt(offset[i], fx[i], fy[i]), level.Sample(u[i], v[i])) << i;
  }
}

}  // namespace
}  // namespace gazedirector
