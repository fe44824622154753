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

// The iris texture has hues of its own (an orange ring, a dark rim); matched
// channel by channel, a pixel of another hue than the rendering's median
// kept that difference, and a grey-green iris got brown specks (d19.jpg).
// The rendered iris now takes the photo iris's colour, only its brightness
// following the rendering.
TEST(EyeColourMatchTest, TheRenderedIrisTakesThePhotoIrissHueAtEveryBrightness) {
  EyeColourMatch match;
  for (int i = 0; i <= 40; ++i) {
    const float t = i / 40.0f;
    const float photo = 0.3f + 0.1f * t, rendered = 0.3f + 0.2f * t;
    match.Add({0.9f * photo, photo, 0.95f * photo}, {rendered, rendered, rendered}, /*sclera=*/false);
    match.Add({0.8f, 0.8f, 0.85f}, {0.9f, 0.9f, 0.9f}, /*sclera=*/true);
  }
  match.Finish();
  for (const cv::Vec3f& rendered : {cv::Vec3f(0.1f, 0.25f, 0.4f), cv::Vec3f(0.45f, 0.4f, 0.3f)}) {
    const cv::Vec3f matched = match.Match(rendered, false, {});
    EXPECT_NEAR(matched[0] / matched[1], 0.9f, 0.01f) << rendered;
    EXPECT_NEAR(matched[2] / matched[1], 0.95f, 0.01f) << rendered;
  }
  // Brightness follows the rendering's, at the photo's contrast.
  EXPECT_LT(Luminance(match.Match({0.1f, 0.25f, 0.4f}, false, {})),
            Luminance(match.Match({0.4f, 0.4f, 0.4f}, false, {})));
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

// Samples of one eye: an even iris at `iris` and sclera at `sclera` (grey).
void AddEye(EyeColourMatches& matches, int eye, float iris, float sclera) {
  for (int i = 0; i < 40; ++i) {
    matches.Add(eye, {iris, iris, iris}, {0.4f, 0.4f, 0.4f}, /*sclera=*/false);
    matches.Add(eye, {sclera, sclera, sclera}, {0.9f, 0.9f, 0.9f}, /*sclera=*/true);
  }
}

// One eye in shade, the other lit twice as brightly: each keeps its own
// thresholds and iris colour, which both eyes' samples would blur together.
TEST(EyeColourMatchTest, EachEyeIsMatchedInItsOwnLight) {
  EyeColourMatches matches;
  AddEye(matches, 0, 0.10f, 0.15f);
  AddEye(matches, 1, 0.20f, 0.30f);
  matches.Finish();
  EXPECT_NEAR(matches[0].Match({0.4f, 0.4f, 0.4f}, false, {})[0], 0.10f, 1e-4);
  EXPECT_NEAR(matches[1].Match({0.4f, 0.4f, 0.4f}, false, {})[0], 0.20f, 1e-4);
  EXPECT_NEAR(matches[1].bright_iris(), 0.20f + 0.6f * 0.10f, 1e-4);
  EXPECT_NEAR(matches[0].dark_sclera(), 0.7f * 0.15f, 1e-4);
  EXPECT_NEAR(matches[1].dark_sclera(), 0.7f * 0.30f, 1e-4);
}

// An eye whose "iris" is nearly as bright as its sclera was fitted beside its
// iris: it takes both eyes' match, whose bright-iris threshold the other
// eye's dark iris keeps low enough to tell its sclera from iris.
TEST(EyeColourMatchTest, AnEyeWhoseIrisLooksLikeItsScleraTakesBothEyesMatch) {
  EyeColourMatches matches;
  AddEye(matches, 0, 0.76f, 0.85f);  // darker by 0.11 of the sclera
  AddEye(matches, 1, 0.19f, 0.58f);  // by 0.67
  matches.Finish();
  EXPECT_EQ(&matches[0], &matches.both());
  EXPECT_NE(&matches[1], &matches.both());
  EXPECT_LT(matches[0].bright_iris(), 0.76f);
}

}  // namespace
}  // namespace gazedirector
