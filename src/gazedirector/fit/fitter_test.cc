#include "gazedirector/fit/fitter.h"

#include <cmath>
#include <cstdio>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "gazedirector/fit/fit_options.h"
#include "gazedirector/fit/initialization.h"
#include "gazedirector/fit/landmark_model.h"
#include "gazedirector/geometry/rotation.h"
#include "gazedirector/render/renderer.h"
#include "gazedirector/util/thread_pool.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::SharedModel;

// A 64x64 crop of the subject's left eye rendered from a known Φ: the mean
// shape framed as Fitter::EyePatchStart frames it (scaled to the eye, as the
// Columbia crops are), turned and looking as asked.
cv::Mat RenderEyePatch(const Fitter& fitter, double head_yaw, double pitch, double yaw) {
  const cv::Size size(64, 64);
  Parameters phi = fitter.EyePatchStart(size, kLeftEye, EyePatchFraming::GivenHeadYaw(head_yaw));
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

// The eye's corners on the crop, in pixels (x of the inner, x of the outer).
Eigen::Vector2d CornerColumns(const Fitter& fitter, const Parameters& phi, cv::Size size) {
  const Camera camera = Fitter::EyePatchCamera(size);
  const auto corners = ModelEyeCorners(phi, fitter.model(), kLeftEye);
  return {camera.Project(corners[0]).x(), camera.Project(corners[1]).x()};
}

// Crops are scaled to the eye (Columbia's mean crops show it as wide at head
// poses +-30 as at 0): a given turn of the head keeps the corners where a
// frontal head has them, nearer or farther as the turn foreshortens the eye;
// a read turn does so only where it reads the head clearly turned.
TEST(FitterTest, AnEyePatchIsScaledToTheEyeAtEveryTurnOfTheHead) {
  const Fitter fitter(SharedModel());
  const cv::Size size(64, 64);
  const Parameters frontal = fitter.EyePatchStart(size, kLeftEye);
  const Eigen::Vector2d frontal_corners = CornerColumns(fitter, frontal, size);
  EXPECT_NEAR(std::abs(frontal_corners.y() - frontal_corners.x()), 0.76 * 64, 1.0);
  for (double head_yaw : {-30.0, -15.0, 15.0, 30.0}) {
    const Parameters turned = fitter.EyePatchStart(size, kLeftEye, EyePatchFraming::GivenHeadYaw(head_yaw));
    EXPECT_DOUBLE_EQ(turned.rotation_deg().y(), head_yaw);
    const Eigen::Vector2d corners = CornerColumns(fitter, turned, size);
    EXPECT_NEAR(corners.y() - corners.x(), frontal_corners.y() - frontal_corners.x(), 0.1) << head_yaw;
    EXPECT_NEAR(corners.x() + corners.y(), 2 * Fitter::EyePatchCamera(size).cx, 0.1) << head_yaw;
  }
  // Turned 30 degrees, this eye's outer corner turns away: it shows a quarter
  // narrower, so the head comes about a third nearer.
  const EyePatchFraming away = EyePatchFraming::GivenHeadYaw(-30);
  EXPECT_LT(fitter.EyePatchStart(size, kLeftEye, away).translation().z(), 0.8 * frontal.translation().z());
  // Read, a few degrees are taken for a frontal head; 30 as given.
  const EyePatchFraming read_away{.head_yaw = -30, .head_yaw_read = true};
  EXPECT_NEAR(read_away.FramingYaw(), -30, 0.5);
  const EyePatchFraming nearly_frontal{.head_yaw = 4, .head_yaw_read = true};
  EXPECT_NEAR(nearly_frontal.FramingYaw(), 0, 0.5);
  const Parameters read = fitter.EyePatchStart(size, kLeftEye, nearly_frontal);
  EXPECT_DOUBLE_EQ(read.rotation_deg().y(), 4);
  EXPECT_NEAR(read.translation().z(), frontal.translation().z(), 0.01 * frontal.translation().z());
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
  const FitResult fit = fitter.FitEyePatchAt(crop, kLeftEye, 0, 0, EyePatchFraming::GivenHeadYaw(c.head_yaw));
  // A head turned 30 degrees foreshortens the eye whose outer corner turns
  // away by a quarter, and the crop, scaled to the eye, magnifies it again:
  // there (head yaw -30 for this eye) pitch is read 1-3 degrees low even by a
  // fit started at the true gaze, so the energy's minimum, not the path, sits
  // there. Pitch 5, yaw -42: 2.5 low started at the true gaze; from the
  // fit's own start under 3 low on the Xeon builds of sessions 31-45 and 3.2
  // low, at an 11% higher energy, on an AMD EPYC build (-march=native).
  EXPECT_NEAR(fit.phi.gaze_pitch(), c.pitch, std::abs(c.head_yaw) >= 30 ? 3.5 : 2.0);
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

// The Jacobian's columns are spread over the threads, each rendered in
// whichever thread's workspace takes it, the exact ones beside them: a fit
// comes out the same, to the last bit, with one thread or three, fresh from
// the landmarks or warm.
TEST(FitterTest, AFitIsTheSameWithAnyNumberOfThreads) {
  const testing::FittedStill& still = testing::FitStill("images/d30.jpg");
  ASSERT_EQ(still.faces.size(), 1u);
  Fitter one(SharedModel(), FitOptions{}, std::make_shared<ThreadPool>(1));
  Fitter three(SharedModel(), FitOptions{}, std::make_shared<ThreadPool>(3));
  const FitResult fresh = one.FitFace(still.image, still.camera, still.faces[0]);
  EXPECT_EQ(three.FitFace(still.image, still.camera, still.faces[0]).phi.values, fresh.phi.values);
  Parameters start = fresh.phi;
  start.gaze_yaw() += 4;
  start.block<Block::kLightDirection>() += Eigen::Vector2d(5, -5);
  EXPECT_EQ(three.FitFace(still.image, still.camera, still.faces[0], &start).phi.values,
            one.FitFace(still.image, still.camera, still.faces[0], &start).phi.values);
}

// d19.jpg is lit brightly: his pupils are about 4 px across in irises of
// about 22 (0.18 of the iris's radius), far from the eyeball texture's 0.49.
// The fit narrows them; left at the texture's, the black disc read as
// light on his iris (the environment's highlights) in redirection.
TEST(FitterTest, PupilsNarrowedByBrightLightAreFittedNarrow) {
  const testing::FittedStill& still = testing::FitStill("images/d19.jpg");
  ASSERT_TRUE(still.fit.good) << still.fit.note;
  std::printf("pupil size %.3f, iris size %.3f\n", still.fit.phi.pupil_size(), still.fit.phi.iris_size());
  EXPECT_LT(still.fit.phi.pupil_size(), 0.3);
}

// A face a quarter turn in the photo (a phone held sideways, its picture not
// marked to be turned) is fitted as the same face upright: the same gaze
// relative to the head, the head rolled by the quarter.
TEST(FitterTest, AFaceTurnedAQuarterInThePhotoIsFittedAsUpright) {
  const testing::FittedStill& upright = testing::FitStill("images/s12.jpg");
  ASSERT_EQ(upright.faces.size(), 1u);
  ASSERT_TRUE(upright.fit.good) << upright.fit.note;
  cv::Mat turned;
  cv::rotate(upright.image, turned, cv::ROTATE_90_CLOCKWISE);
  const Camera camera = Camera::Default(turned.cols, turned.rows);
  const std::vector<Face> faces = testing::MakeFaceTracker().DetectFaces(turned, camera);
  ASSERT_EQ(faces.size(), 1u);
  const FitResult fit = Fitter(SharedModel()).FitFace(turned, camera, faces[0]);
  EXPECT_TRUE(fit.good) << fit.note;
  std::printf("turned: pitch %.1f against %.1f, yaw %.1f against %.1f\n", fit.phi.gaze_pitch(),
              upright.fit.phi.gaze_pitch(), fit.phi.gaze_yaw(), upright.fit.phi.gaze_yaw());
  // Measured: pitch -2.6 against -1.9, yaw 4.2 against 3.4 (session 75; 4.1 / 3.5 in
  // session 74, -2.2 / -1.6 and 3.1 / 4.8 before; the landmarks differ by 1% of the
  // eye-corner distance, the rasters by their pixels).
  EXPECT_NEAR(fit.phi.gaze_pitch(), upright.fit.phi.gaze_pitch(), 2.5);
  EXPECT_NEAR(fit.phi.gaze_yaw(), upright.fit.phi.gaze_yaw(), 2.5);
  // The camera turned a quarter about its axis, clockwise as the photo shows it.
  const Eigen::AngleAxisd turn(fit.phi.rotation() * upright.fit.phi.rotation().transpose());
  EXPECT_NEAR(RadToDeg(turn.angle()), 90.0, 3.0);  // measured 90.2
  EXPECT_GT(turn.axis().z(), 0.99);
}

}  // namespace
}  // namespace gazedirector
