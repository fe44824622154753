#include "gazedirector/fit/fitter.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "gazedirector/fit/fit_options.h"
#include "gazedirector/fit/landmark_model.h"
#include "gazedirector/render/renderer.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::SharedModel;

// A 64x64 crop of the subject's left eye rendered from a known Φ: the mean
// shape framed as Fitter::EyePatchStart frames it, turned and looking as asked.
cv::Mat RenderEyePatch(const Fitter& fitter, double head_yaw, double pitch, double yaw) {
  const cv::Size size(64, 64);
  Parameters phi = fitter.EyePatchStart(size, kLeftEye);
  phi.block<Block::kRotation>() = Eigen::Vector3d(0, head_yaw, 0);
  phi.gaze_pitch() = pitch;
  phi.eyelid_pitch() = pitch;
  phi.gaze_yaw() = yaw;
  // Framed as the crops are: the mean of the eye's six landmarks at the centre.
  const Camera camera = Fitter::EyePatchCamera(size);
  const LandmarkModel centre = LandmarkModel(*SharedModel()).EyeCentre(kLeftEye);
  Renderer renderer(SharedModel());
  renderer.set_eyes(true, false);
  for (int pass = 0; pass < 3; ++pass) {
    renderer.Pose(phi);
    std::vector<Eigen::Vector2d> projected;
    centre.Project(renderer.posed(), camera, projected);
    const double depth = phi.block<Block::kTranslation>().z();
    phi.block<Block::kTranslation>().x() -= (projected[0].x() - camera.cx) * depth / camera.fx;
    phi.block<Block::kTranslation>().y() -= (projected[0].y() - camera.cy) * depth / camera.fy;
  }
  RenderBuffers buffers;
  renderer.Render(phi, camera, buffers);
  return buffers.ColourImage(cv::Mat(size, CV_8UC3, cv::Scalar(110, 140, 190)));
}

struct SyntheticCase {
  double head_yaw, pitch, yaw;
};

class SyntheticEyePatchTest : public ::testing::TestWithParam<SyntheticCase> {};

// The model's own renders are the one input whose gaze is known exactly:
// the fit must find it again, also with the head turned (given its yaw).
TEST_P(SyntheticEyePatchTest, RecoversTheRenderedGaze) {
  const SyntheticCase c = GetParam();
  FitOptions options = EyePatchFitOptions({});  // as the Columbia crops are fitted
  options.free[LayoutOf(Block::kRotation).offset + 1] = false;  // the head's yaw is given
  Fitter fitter(SharedModel(), options);
  const cv::Mat crop = RenderEyePatch(fitter, c.head_yaw, c.pitch, c.yaw);
  const FitResult fit = fitter.FitEyePatchAt(crop, kLeftEye, 0, 0, 0.76, c.head_yaw);
  EXPECT_NEAR(fit.phi.gaze_pitch(), c.pitch, 2.0);
  EXPECT_NEAR(EyeRegionModel::EyeYaw(fit.phi, kLeftEye), c.yaw, 2.0);
}

INSTANTIATE_TEST_SUITE_P(Gazes, SyntheticEyePatchTest,
                         ::testing::Values(SyntheticCase{0, 0, 0}, SyntheticCase{0, -8, 12}, SyntheticCase{0, 8, -12},
                                           SyntheticCase{30, 0, 0}, SyntheticCase{-30, 0, 10},
                                           // Looking past the lens from a turned head: 40 degrees in the head.
                                           SyntheticCase{30, 0, 40}, SyntheticCase{-30, 5, -42}),
                         [](const ::testing::TestParamInfo<SyntheticCase>& info) {
                           auto name = [](const char* what, double value) {
                             return std::string(what) + (value < 0 ? "Minus" : "") + std::to_string(std::abs(static_cast<int>(value)));
                           };
                           const SyntheticCase& c = info.param;
                           return name("Head", c.head_yaw) + name("Pitch", c.pitch) + name("Yaw", c.yaw);
                         });

// A refit of a video's face starts afresh from the landmarks but keeps what
// the options hold (its settled shape and texture) at the values given.
TEST(FitterTest, ARefitKeepsTheHeldParametersAndFindsTheGaze) {
  const testing::FittedStill& still = testing::FitStill("images/d30.jpg");
  ASSERT_EQ(still.faces.size(), 1u);
  const FitResult& first = still.fit;
  ASSERT_TRUE(first.good) << first.note;
  ASSERT_GT(first.phi.shape().norm(), 0.5);  // far enough from the mean to tell

  FitOptions holding;
  Hold(holding.free, {Block::kShape, Block::kTexture});
  Fitter fitter(SharedModel(), holding);
  const FitResult refit = fitter.RefitFace(still.image, still.camera, still.faces[0], first.phi);
  EXPECT_EQ(refit.phi.shape(), first.phi.shape());
  EXPECT_EQ(refit.phi.texture(), first.phi.texture());
  EXPECT_TRUE(refit.good) << refit.note;
  EXPECT_NEAR(refit.phi.gaze_pitch(), first.phi.gaze_pitch(), 3.0);
  EXPECT_NEAR(refit.phi.gaze_yaw(), first.phi.gaze_yaw(), 3.0);
  EXPECT_LT(refit.terms.total(), 1.1 * first.terms.total());
}

}  // namespace
}  // namespace gazedirector
