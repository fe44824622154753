#include "gazedirector/redirect/eye_colour_match.h"

#include <gtest/gtest.h>

#include "gazedirector/redirect/eye_image.h"

namespace gazedirector {
namespace {

// A rendered iris with a brighter ring (0.3-0.5) matched to a photo's dark,
// even brown iris (0.10-0.14 in red): the rendering's median lands on the
// photo's and its spread shrinks to the photo's.
TEST(EyeColourMatchTest, TheRenderedIrisTakesThePhotoIrissMedianAndSpread) {
  EyeColourMatch match;
  for (int i = 0; i <= 40; ++i) {
    const float t = i / 40.0f;
    const float photo = 0.10f + 0.04f * t, rendered = 0.3f + 0.2f * t;
    match.Add({photo * 0.5f, photo * 0.7f, photo}, {rendered, rendered, rendered}, /*sclera=*/false);
    match.Add({0.8f, 0.8f, 0.85f}, {0.9f, 0.9f, 0.9f}, /*sclera=*/true);
  }
  match.Finish();
  ASSERT_TRUE(match.sclera_known());
  const cv::Vec3f median = match.Match({0.4f, 0.4f, 0.4f}, false, {});
  EXPECT_NEAR(median[2], 0.12f, 1e-3);
  EXPECT_NEAR(median[0], 0.06f, 1e-3);
  const cv::Vec3f brightest = match.Match({0.5f, 0.5f, 0.5f}, false, {});
  EXPECT_NEAR(brightest[2] - median[2], 0.02f, 2e-3);  // the photo's half-spread, not the rendering's 0.1
  // Sclera: the colour given (the photo's sclera nearby), never brighter.
  const cv::Vec3f nearby(0.7f, 0.75f, 0.8f);
  EXPECT_EQ(match.Match({0.9f, 0.9f, 0.9f}, true, nearby), nearby);
  EXPECT_LT(Luminance(match.Match({0.5f, 0.5f, 0.5f}, true, nearby)), Luminance(nearby));
  // Thresholds between them: 0.7 of the sclera's luminance, and 0.6 of the
  // way from the iris's luminance to the sclera's.
  EXPECT_NEAR(match.dark_sclera(), 0.7f * Luminance({0.8f, 0.8f, 0.85f}), 1e-4);
  EXPECT_GT(match.bright_iris(), 0.4f);
  EXPECT_LT(match.bright_iris(), 0.6f);
}

TEST(EyeColourMatchTest, TooFewSamplesLeaveTheRenderingAsItIs) {
  EyeColourMatch match;
  for (int i = 0; i < 5; ++i) {
    match.Add({0.1f, 0.1f, 0.1f}, {0.4f, 0.4f, 0.4f}, false);
    match.Add({0.8f, 0.8f, 0.8f}, {0.9f, 0.9f, 0.9f}, true);
  }
  match.Finish();
  EXPECT_FALSE(match.sclera_known());
  EXPECT_EQ(match.dark_sclera(), -1.0f);
  EXPECT_EQ(match.bright_iris(), -1.0f);
  EXPECT_EQ(match.Match({0.4f, 0.3f, 0.2f}, false, {}), cv::Vec3f(0.4f, 0.3f, 0.2f));
  EXPECT_EQ(match.Match({0.9f, 0.9f, 0.9f}, true, {}), cv::Vec3f(0.9f, 0.9f, 0.9f));
}

}  // namespace
}  // namespace gazedirector
