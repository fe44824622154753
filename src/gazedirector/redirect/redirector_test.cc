#include "gazedirector/redirect/redirector.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "gazedirector/fit/face_fit.h"
#include "gazedirector/fit/fitter.h"
#include "gazedirector/io/image_io.h"
#include "gazedirector/io/video_reader.h"
#include "gazedirector/video/gaze_tracker.h"
#include "gazedirector/model/eye_region_topology.h"
#include "gazedirector/redirect/gaze_target.h"
#include "gazedirector/util/statistics.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::SharedModel;

// d30.jpg (a near-frontal portrait) with its model fitted, once per test binary.
const testing::FittedStill& Photo() {
  static const testing::FittedStill& photo = []() -> const testing::FittedStill& {
    const testing::FittedStill& still = testing::FitStill("images/d30.jpg");
    EXPECT_TRUE(still.fit.good) << still.fit.note;
    return still;
  }();
  return photo;
}

// Photo() redirected from `fitted` to `target`, with what --debug-dir shows.
struct Redirected {
  cv::Mat image;
  RedirectLayers layers;
  RedirectReport report;
};

Redirected RedirectPhoto(Redirector& redirector, const Parameters& fitted, const Parameters& target,
                         const testing::FittedStill& p = Photo()) {
  Redirected redirected{p.image.clone(), {}, {}};
  redirected.report = redirector.Redirect(redirected.image, p.camera, fitted, target, &redirected.layers);
  return redirected;
}

// The centroid of the darkest pixels (the irises and pupils) among the
// eyeball pixels of `mask` in `image`, corneal highlights filled in (they move
// less than the iris and would pull the centroid away from themselves).
cv::Point2d DarkCentroid(const cv::Mat& image, const cv::Mat& mask) {
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  cv::morphologyEx(grey, grey, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
  std::vector<uchar> values;
  for (int i = 0; i < grey.rows * grey.cols; ++i) {
    if (mask.data[i]) values.push_back(grey.data[i]);
  }
  std::nth_element(values.begin(), values.begin() + values.size() / 5, values.end());
  const uchar threshold = values[values.size() / 5];
  cv::Point2d sum(0, 0);
  double count = 0;
  for (int i = 0; i < grey.rows * grey.cols; ++i) {
    if (mask.data[i] && grey.data[i] <= threshold) sum += cv::Point2d(i % grey.cols, i / grey.cols), ++count;
  }
  return sum / count;
}

TEST(RedirectorTest, RedirectingToTheFittedGazeChangesLittleAndNothingOutside) {
  const testing::FittedStill& p = Photo();
  Redirector redirector(SharedModel());
  cv::Mat result = p.image.clone();
  const RedirectReport report = redirector.Redirect(result, p.camera, p.fit.phi, p.fit.phi);
  ASSERT_TRUE(report.redirected[0] && report.redirected[1]) << report.note;
  cv::Mat outside = cv::Mat::ones(p.image.size(), CV_8UC1) * 255;
  outside(report.region).setTo(0);
  cv::Mat difference;
  cv::absdiff(result, p.image, difference);
  EXPECT_EQ(cv::norm(difference, cv::NORM_INF, outside), 0.0);
  // Only the seam's blur and the swapped highlights may differ (the photo's
  // own eye is reused right up to the lid margin, less the faint reflections
  // the chosen environment explains there, which are then added back): 0.22
  // levels on average, 0.11 before the seam was softened (session 62); 0.29
  // with the photo's share faded at the mask's edge, the highlights cut out
  // and its darker sclera replaced.
  EXPECT_LT(cv::mean(difference(report.region))[1], 0.3);
}

TEST(RedirectorTest, YawMovesTheIrisesTheWayAndByAboutTheAmountTheModelPredicts) {
  const testing::FittedStill& p = Photo();
  Redirector redirector(SharedModel());
  const Parameters target = Retarget(p.fit.phi, GazeTarget::Offset(0, 15));  // toward the subject's left: image right
  const Redirected still = RedirectPhoto(redirector, p.fit.phi, p.fit.phi);
  const Redirected moved = RedirectPhoto(redirector, p.fit.phi, target);
  const RedirectReport& report = moved.report;
  ASSERT_TRUE(report.redirected[0] && report.redirected[1]) << report.note;
  // Over the same pixels before and after: the eye openings of both.
  cv::Mat both;
  cv::bitwise_or(still.layers.eyeball_mask, moved.layers.eyeball_mask, both);
  // Each eye on its own (the region's halves), then their mean.
  cv::Point2d before(0, 0), after(0, 0);
  for (int half = 0; half < 2; ++half) {
    cv::Mat mask = both.clone();
    mask(cv::Rect(half == 0 ? mask.cols / 2 : 0, 0, mask.cols - mask.cols / 2, mask.rows)).setTo(0);
    before += 0.5 * DarkCentroid(still.image(report.region), mask);
    after += 0.5 * DarkCentroid(moved.image(report.region), mask);
  }
  // The model's own prediction: the mean image motion of the two iris centres
  // (10.5 mm in front of the eyeball centres).
  double predicted = 0;
  const std::array<EyeGaze, 2> from = EyeGazes(p.fit.phi), to = EyeGazes(target);
  for (int eye = 0; eye < 2; ++eye) {
    predicted += 0.5 * (p.camera.Project(to[eye].centre + 10.5 * to[eye].gaze) -
                        p.camera.Project(from[eye].centre + 10.5 * from[eye].gaze)).x();
  }
  EXPECT_GT(after.x - before.x, 0.7 * predicted);
  EXPECT_LT(after.x - before.x, 1.4 * predicted);
  EXPECT_LT(std::abs(after.y - before.y), 0.3 * predicted);
}

// The glint of one eye: the near-white pixels (grey level 200 and more) on
// its iris (within 0.9 radii of the iris centre that `phi` puts in the image
// of `camera`), how many there are, their centroid and where they are.
struct Glint {
  int pixels = 0;
  cv::Point2d centroid;
  cv::Mat mask;  // 8-bit, the image's size
};
// The centre of `eye`'s iris (its limbus ring's) that `phi` puts in the camera frame.
Eigen::Vector3d IrisCentre(const Parameters& phi, int eye) {
  const EyeGaze gaze = EyeGazes(phi)[eye];
  return gaze.centre + topology::kLimbusDepthMm * gaze.gaze;
}

Glint GlintOnIris(const cv::Mat& image, const Camera& camera, const Parameters& phi, int eye) {
  const Eigen::Vector3d centre = IrisCentre(phi, eye);
  const Eigen::Vector2d at = camera.Project(centre);
  const double radius = camera.fx * topology::kLimbusRadiusMm * phi.iris_size() / centre.z();
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  Glint glint;
  glint.mask = cv::Mat(image.size(), CV_8UC1, cv::Scalar(0));
  cv::Point2d sum(0, 0);
  for (int y = static_cast<int>(at.y() - radius); y <= static_cast<int>(at.y() + radius); ++y) {
    for (int x = static_cast<int>(at.x() - radius); x <= static_cast<int>(at.x() + radius); ++x) {
      if (std::hypot(x - at.x(), y - at.y()) < 0.9 * radius && grey.at<uchar>(y, x) >= 200) {
        sum += cv::Point2d(x, y), ++glint.pixels;
        glint.mask.at<uchar>(y, x) = 255;
      }
    }
  }
  if (glint.pixels > 0) glint.centroid = sum / glint.pixels;
  return glint;
}

// Left where they were, d30's glints come back as they were, and so does
// the iris around them. The chosen environment's highlight there, which the
// glint's fill has taken away already, was taken off the fill a second time
// until session 66: a dark rim beside each glint (as far as 88 grey levels
// below the photo here; redirected to the camera s42.jpg showed a black dash
// under her glint).
TEST(RedirectorTest, GlintsLeftWhereTheyWereComeBackAsTheyWere) {
  const testing::FittedStill& p = Photo();
  Redirector redirector(SharedModel());
  const Redirected at_rest = RedirectPhoto(redirector, p.fit.phi, p.fit.phi);
  ASSERT_TRUE(at_rest.report.redirected[0] && at_rest.report.redirected[1]) << at_rest.report.note;
  cv::Mat difference;
  cv::absdiff(at_rest.image, p.image, difference);
  // Inside the eyeballs, clear of the seam's blur at the lids.
  cv::Mat inside(p.image.size(), CV_8UC1, cv::Scalar(0));
  cv::erode(at_rest.layers.eyeball_mask, inside(at_rest.report.region),
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
  for (int eye = 0; eye < 2; ++eye) {
    const Glint glint = GlintOnIris(p.image, p.camera, p.fit.phi, eye);
    ASSERT_GE(glint.pixels, 4);
    cv::Mat around;
    cv::dilate(glint.mask, around, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(7, 7)));
    around &= inside;
    const double most = cv::norm(difference, cv::NORM_INF, around);
    std::printf("eye %d: %d glint pixels, at most %.0f grey levels changed within 3 px of them\n", eye,
                glint.pixels, most);
    EXPECT_LE(most, 40.0);
  }
}

// d30's corneal glints (a studio light's) stay when the eyes turn, and move
// as the cornea's centre of curvature does (6.22 mm in front of the eyeball
// centre), about 0.58 of the iris's motion (0.62 measured): carried with the
// photo's iris they would keep their place on it (1). The environment map's
// reflections that replaced them until session 60 left at most one of these glint
// pixels in any of the eight eyes.
TEST(RedirectorTest, GlintsStayAndMoveWithTheCorneasCurvature) {
  const testing::FittedStill& p = Photo();
  Redirector redirector(SharedModel());
  double mean_along = 0;
  int cases = 0;
  for (const auto& [pitch, yaw] :
       {std::pair(10.0, 0.0), std::pair(0.0, 15.0), std::pair(0.0, -15.0), std::pair(-10.0, 0.0)}) {
    const Parameters target = Retarget(p.fit.phi, GazeTarget::Offset(pitch, yaw));
    const Redirected moved = RedirectPhoto(redirector, p.fit.phi, target);
    ASSERT_TRUE(moved.report.redirected[0] && moved.report.redirected[1]) << moved.report.note;
    for (int eye = 0; eye < 2; ++eye) {
      const Glint before = GlintOnIris(p.image, p.camera, p.fit.phi, eye);
      const Glint after = GlintOnIris(moved.image, p.camera, target, eye);
      ASSERT_GE(before.pixels, 4);
      // On the iris, relative to its centre, the glint moves back by 1 - 0.58 of the iris's motion.
      const Eigen::Vector2d iris =
          p.camera.Project(IrisCentre(target, eye)) - p.camera.Project(IrisCentre(p.fit.phi, eye));
      const cv::Point2d glint_motion = after.centroid - before.centroid;
      const double along = (glint_motion.x * iris.x() + glint_motion.y * iris.y()) / iris.squaredNorm();
      std::printf("pitch %+.0f yaw %+.0f, eye %d: glint pixels %d -> %d, iris moved %.1f px, the glint %.2f of it\n",
                  pitch, yaw, eye, before.pixels, after.pixels, iris.norm(), along);
      // The glint may leave the measured disc or slip under a lid in part.
      EXPECT_GE(after.pixels, std::max(2, before.pixels / 4));
      EXPECT_GT(along, 0.0);
      EXPECT_LT(along, 1.5);
      mean_along += along, ++cases;
    }
  }
  mean_along /= cases;
  std::printf("the glints moved %.2f of the irises' motion on average\n", mean_along);
  EXPECT_GT(mean_along, 0.4);
  EXPECT_LT(mean_along, 0.8);
}

// Mean luminance and redness ((R - G) / (R + G + B)) of the pixels of `image` under `mask`,
// and the fraction of them darker than `dark`.
struct Tone {
  double luminance = 0, redness = 0, dark_fraction = 0;
};
Tone ToneUnder(const cv::Mat& image, const cv::Mat& mask, double dark) {
  Tone tone;
  int count = 0;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      if (!mask.at<uchar>(y, x)) continue;
      const cv::Vec3b bgr = image.at<cv::Vec3b>(y, x);
      const double luminance = 0.114 * bgr[0] + 0.587 * bgr[1] + 0.299 * bgr[2];
      tone.luminance += luminance;
      tone.redness += (bgr[2] - bgr[1]) / std::max(1.0, double(bgr[0]) + bgr[1] + bgr[2]);
      tone.dark_fraction += luminance < dark;
      ++count;
    }
  }
  if (count > 0) tone.luminance /= count, tone.redness /= count, tone.dark_fraction /= count;
  return tone;
}

// The sclera a redirection to the fitted gaze shows, less its outermost
// pixels (lids, lashes, the iris's rim): the photo's own sclera.
cv::Mat ShownSclera(const Redirected& at_rest) {
  cv::Mat shown;
  cv::erode(at_rest.layers.sclera_mask, shown, cv::Mat());
  return shown;
}

// Turned by 40 degrees, the eyes show sclera the photo never did (hidden
// under the lids or behind the iris): it must look like the photo's own
// sclera, not like the pink periphery of the eyeball texture, the skin a
// slightly wide fit let in, or the lashes' shade dragged across the white.
TEST(RedirectorTest, ALargeTurnShowsCleanSclera) {
  const testing::FittedStill& p = Photo();
  Redirector redirector(SharedModel());
  const Redirected at_rest = RedirectPhoto(redirector, p.fit.phi, p.fit.phi);
  const cv::Mat shown = ShownSclera(at_rest);
  const Tone photo = ToneUnder(p.image(at_rest.report.region), shown, 0);
  ASSERT_GT(cv::countNonZero(shown), 30);
  for (double yaw : {-40.0, 40.0}) {
    const Redirected turned = RedirectPhoto(redirector, p.fit.phi, Retarget(p.fit.phi, GazeTarget::Offset(0, yaw)));
    const RedirectReport& report = turned.report;
    ASSERT_TRUE(report.redirected[0] && report.redirected[1]) << report.note;
    cv::Mat inner;
    cv::erode(turned.layers.sclera_mask, inner, cv::Mat(), cv::Point(-1, -1), 2);
    ASSERT_GT(cv::countNonZero(inner), 30);
    const Tone tone = ToneUnder(turned.image(report.region), inner, 0.6 * photo.luminance);
    std::printf("yaw %+.0f: sclera luminance %.1f (photo %.1f), redness %.3f (photo %.3f), dark %.3f\n", yaw,
                tone.luminance, photo.luminance, tone.redness, photo.redness, tone.dark_fraction);
    EXPECT_NEAR(tone.redness, photo.redness, 0.03) << "yaw " << yaw;
    EXPECT_NEAR(tone.luminance, photo.luminance, 0.2 * photo.luminance) << "yaw " << yaw;
    EXPECT_LT(tone.dark_fraction, 0.1) << "yaw " << yaw;
  }
}

// d19.jpg: a dim photo of small eyes whose sclera shows as two narrow
// triangles, darkened by the lids and lashes around them. Turned 15 degrees
// up, the sclera bared below the iris is rendered, coloured by the photo's
// sclera reused nearby or else by the photo's clear sclera (the brighter
// half of the sclera the fit showed away from its lids). Coloured by the
// median of the sclera reused (mostly lid-shaded) where none was reused
// nearby, it read 90.5 grey levels against the photo's 97.5 (0.93); 94.7 in
// session 63, 94.2 in session 73 (0.97). Since session 74 the fit places his
// irises closer to the photo's (`eval iris` 0.13 -> 0.10 iris radii), so less
// of their rim falls in the sclera it shows: 98.0 against 103.4 (0.95).
TEST(RedirectorTest, ScleraBaredBelowALiftedIrisIsAsLightAsThePhotosSclera) {
  const testing::FittedStill& p = testing::FitStill("images/d19.jpg");
  ASSERT_TRUE(p.fit.good) << p.fit.note;
  Redirector redirector(SharedModel());
  const Redirected at_rest = RedirectPhoto(redirector, p.fit.phi, p.fit.phi, p);
  const cv::Mat shown = ShownSclera(at_rest);
  ASSERT_GT(cv::countNonZero(shown), 20);
  const Tone photo = ToneUnder(p.image(at_rest.report.region), shown, 0);
  const Redirected up = RedirectPhoto(redirector, p.fit.phi, Retarget(p.fit.phi, GazeTarget::Offset(15, 0)), p);
  ASSERT_TRUE(up.report.redirected[0] && up.report.redirected[1]) << up.report.note;
  const cv::Mat rendered = up.layers.sclera_mask & ~up.layers.transfer_mask;
  ASSERT_GT(cv::countNonZero(rendered), 30);
  const Tone bared = ToneUnder(up.layers.eyeball_layer, rendered, 0);
  std::printf("photo sclera %.1f, rendered sclera below the lifted iris %.1f\n", photo.luminance, bared.luminance);
  EXPECT_GT(bared.luminance, 0.94 * photo.luminance);
  EXPECT_LT(bared.luminance, 1.3 * photo.luminance);
}

// The sclera of the new eyeballs in the top `rows` pixels of each of their
// columns: the band under the upper lids.
cv::Mat UnderTheUpperLids(const RedirectLayers& layers, int rows) {
  cv::Mat band(layers.eyeball_mask.size(), CV_8UC1, cv::Scalar(0));
  for (int x = 0; x < band.cols; ++x) {
    for (int y = 0, shown = 0; y < band.rows && shown < rows; ++y) {
      if (!layers.eyeball_mask.at<uchar>(y, x)) continue;
      if (layers.sclera_mask.at<uchar>(y, x)) band.at<uchar>(y, x) = 255;
      ++shown;
    }
  }
  return band;
}

// s42.jpg turned aside: sclera under her upper lashes took mirror images
// across the eyeball's horizontal plane, from low in her eye where no lashes
// shade it, and drew a dotted bright line under them (8.8% / 12.8% of that
// band brighter than nine tenths of her sclera at 10 / 15 degrees, 9.7% in
// the photo's own band; 2.0% / 3.7% now that only the mirror image under
// the same lid serves there).
TEST(RedirectorTest, ScleraUnderTheUpperLashesStaysInTheirShade) {
  const testing::FittedStill& p = testing::FitStill("images/s42.jpg");
  ASSERT_TRUE(p.fit.good) << p.fit.note;
  Redirector redirector(SharedModel());
  const Redirected at_rest = RedirectPhoto(redirector, p.fit.phi, p.fit.phi, p);
  const cv::Mat shown = ShownSclera(at_rest);
  ASSERT_GT(cv::countNonZero(shown), 30);
  // Bright for this photo: brighter than nine tenths of the sclera it shows.
  cv::Mat grey;
  cv::cvtColor(p.image(at_rest.report.region), grey, cv::COLOR_BGR2GRAY);
  std::vector<double> sclera;
  for (int i = 0; i < grey.rows * grey.cols; ++i) {
    if (shown.data[i]) sclera.push_back(grey.data[i]);
  }
  const double bright = Quantile(std::move(sclera), 0.9);
  auto bright_share = [&](const RedirectLayers& layers, const cv::Mat& image) {
    const cv::Mat band = UnderTheUpperLids(layers, 3);
    EXPECT_GT(cv::countNonZero(band), 40);
    return 1 - ToneUnder(image, band, bright).dark_fraction;
  };
  const double photo_share = bright_share(at_rest.layers, p.image(at_rest.report.region));
  for (double yaw : {-15.0, -10.0, 10.0, 15.0}) {
    const Redirected turned = RedirectPhoto(redirector, p.fit.phi, Retarget(p.fit.phi, GazeTarget::Offset(0, yaw)), p);
    ASSERT_TRUE(turned.report.redirected[0] && turned.report.redirected[1]) << turned.report.note;
    const double share = bright_share(turned.layers, turned.layers.eyeball_layer);
    std::printf("yaw %+.0f: %.3f of the band under the upper lids brighter than %.0f (the photo's %.3f)\n", yaw, share,
                bright, photo_share);
    EXPECT_LE(share, photo_share) << "yaw " << yaw;
  }
}

// Columbia 0004's left eye looking ahead, fitted as `eval redirect-columbia`
// fits it: the fitted iris lies a pixel beside the photo's and covers a thin
// crescent of bright sclera along its edge. Taken for a glint, that crescent
// was moved with the cornea and drawn across the new sclera (looking 10
// degrees down / up: 66 / 70 pixels given over 40 grey levels of light, up
// to 120 / 125); the photo shows no glint, and none is added now (at most 15).
// (An L crop shows the eye the model calls its right, ColumbiaCrop::ModelEye.)
TEST(RedirectorTest, ScleraAlongTheFittedIrissEdgeIsNotMovedAsAGlint) {
  const cv::Mat crop = ReadImage(testing::DataPath("columbia-eyes/0004_2m_0P_0V_0H_L.jpg"));
  Fitter fitter(SharedModel());
  const FitResult fit = fitter.FitEyePatch(crop, kRightEye);
  const Camera camera = Fitter::EyePatchCamera(crop.size());
  Redirector redirector(SharedModel());
  for (double pitch : {-10.0, 10.0}) {
    cv::Mat image = crop.clone();
    RedirectLayers layers;
    const RedirectReport report =
        redirector.Redirect(image, camera, fit.phi, Retarget(fit.phi, GazeTarget::Offset(pitch, 0)), &layers);
    ASSERT_TRUE(report.redirected[kRightEye]) << report.note;
    const cv::Mat& added = layers.specular;
    double most = 0;
    cv::minMaxLoc(added, nullptr, &most);
    const int bright = cv::countNonZero(added > 40);
    std::printf("pitch %+.0f: %d pixels given over 40 levels of light, at most %.0f\n", pitch, bright, most);
    EXPECT_LE(bright, 3) << "pitch " << pitch;
  }
}

// How much brighter, in grey levels, rendered sclera pixels are than the
// transferred sclera pixels beside them (4-neighbours) in the composited
// eyeball layer, on average.
double ScleraSeamStep(const RedirectLayers& layers) {
  cv::Mat grey;
  cv::cvtColor(layers.eyeball_layer, grey, cv::COLOR_BGR2GRAY);
  auto sclera = [&](int x, int y) { return layers.sclera_mask.at<uchar>(y, x) != 0; };
  auto transferred = [&](int x, int y) { return layers.transfer_mask.at<uchar>(y, x) != 0; };
  double step = 0;
  int pairs = 0;
  for (int y = 1; y + 1 < grey.rows; ++y) {
    for (int x = 1; x + 1 < grey.cols; ++x) {
      if (!sclera(x, y) || transferred(x, y)) continue;
      for (const cv::Point d : {cv::Point(1, 0), cv::Point(-1, 0), cv::Point(0, 1), cv::Point(0, -1)}) {
        if (!sclera(x + d.x, y + d.y) || !transferred(x + d.x, y + d.y)) continue;
        step += double(grey.at<uchar>(y, x)) - grey.at<uchar>(y + d.y, x + d.x);
        ++pairs;
      }
    }
  }
  EXPECT_GT(pairs, 20);
  return pairs > 0 ? step / pairs : 0;
}

// Where the new gaze shows sclera the photo did not (below the iris looking
// up, beside it looking aside), the rendered sclera must continue the
// photo's sclera beside it, not draw a pale band of the eye's typical white:
// 5.5 / 11.1 / 18.3 grey levels brighter when it took the typical colour
// shaded up to 10% brighter, 1.0 / 5.7 / 10.3 now.
TEST(RedirectorTest, RenderedScleraContinuesThePhotosSclera) {
  const testing::FittedStill& p = Photo();
  Redirector redirector(SharedModel());
  double mean_step = 0;
  for (const auto& [pitch, yaw] : {std::pair(15.0, 0.0), std::pair(0.0, 25.0), std::pair(0.0, -25.0)}) {
    const Redirected result =
        RedirectPhoto(redirector, p.fit.phi, Retarget(p.fit.phi, GazeTarget::Offset(pitch, yaw)));
    ASSERT_TRUE(result.report.redirected[0] && result.report.redirected[1]) << result.report.note;
    const double step = ScleraSeamStep(result.layers);
    std::printf("pitch %+.0f yaw %+.0f: rendered sclera %.1f grey levels brighter than the photo's beside it\n", pitch,
                yaw, step);
    mean_step += step / 3;
  }
  EXPECT_LT(mean_step, 9.0);
}

// Grey level of `image` (8-bit BGR) at the pixels of `mask`, as a list.
std::vector<double> GreyLevels(const cv::Mat& image, const cv::Mat& mask) {
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  std::vector<double> levels;
  for (int i = 0; i < grey.rows * grey.cols; ++i) {
    if (mask.data[i]) levels.push_back(grey.data[i]);
  }
  return levels;
}

// `mask` split between the eyes: its pixels left and right of the middle of
// `eyeballs` (both eyes' mask).
std::array<cv::Mat, 2> MaskByEye(const cv::Mat& mask, const cv::Mat& eyeballs) {
  const cv::Rect both = cv::boundingRect(eyeballs);
  const int middle = both.x + both.width / 2;
  std::array<cv::Mat, 2> halves = {mask.clone(), mask.clone()};
  halves[0].colRange(middle, mask.cols).setTo(0);
  halves[1].colRange(0, middle).setTo(0);
  return halves;
}

// GreyLevels of each eye apart (MaskByEye).
std::array<std::vector<double>, 2> GreyLevelsByEye(const cv::Mat& image, const cv::Mat& mask, const cv::Mat& eyeballs) {
  const std::array<cv::Mat, 2> halves = MaskByEye(mask, eyeballs);
  return {GreyLevels(image, halves[0]), GreyLevels(image, halves[1])};
}

// The median grey levels of each of d30's irises and scleras where its fit
// shows them (her image-right eye is the darker).
struct EyeLevels {
  double iris, sclera;
};
std::array<EyeLevels, 2> PhotoEyeLevels(Redirector& redirector) {
  const testing::FittedStill& p = Photo();
  const Redirected as_fitted = RedirectPhoto(redirector, p.fit.phi, p.fit.phi);
  const RedirectLayers& fitted = as_fitted.layers;
  const cv::Mat region = p.image(as_fitted.report.region);
  const auto irises = GreyLevelsByEye(region, fitted.eyeball_mask & ~fitted.sclera_mask, fitted.eyeball_mask);
  const auto scleras = GreyLevelsByEye(region, fitted.sclera_mask, fitted.eyeball_mask);
  return {EyeLevels{Median(irises[0]), Median(scleras[0])}, EyeLevels{Median(irises[1]), Median(scleras[1])}};
}

// How many of `levels` (each eye's) lie above (`brighter`) or below halfway
// between that eye's iris and sclera levels, as a share of all.
double ShareBeyondHalfway(const std::array<std::vector<double>, 2>& levels, const std::array<EyeLevels, 2>& eyes,
                          bool brighter) {
  double beyond = 0, all = 0;
  for (int eye = 0; eye < 2; ++eye) {
    const double halfway = 0.5 * (eyes[eye].iris + eyes[eye].sclera);
    for (double v : levels[eye]) beyond += brighter ? v > halfway : v < halfway;
    all += static_cast<double>(levels[eye].size());
  }
  return beyond / std::max(all, 1.0);
}

// A fitted iris that sits beside the photo's covers some of its sclera; moved
// with the iris, that sclera used to draw a white crescent inside the new one
// (d14.mp4's far glances, d3.mp4 frame 330). Here d30's fit is turned 6
// degrees off the photo's irises and then redirected 20 degrees back past them.
TEST(RedirectorTest, AnIrisFittedBesideThePhotosCarriesNoScleraIntoTheNewOne) {
  const testing::FittedStill& p = Photo();
  Redirector redirector(SharedModel());
  const std::array<EyeLevels, 2> eyes = PhotoEyeLevels(redirector);
  for (const EyeLevels& eye : eyes) ASSERT_GT(eye.sclera, eye.iris + 40);

  Parameters beside = p.fit.phi;
  beside.gaze_yaw() += 6;
  const Redirected result = RedirectPhoto(redirector, beside, Retarget(beside, GazeTarget::Offset(0, -20)));
  const RedirectReport& report = result.report;
  ASSERT_TRUE(report.redirected[0] && report.redirected[1]) << report.note;
  cv::Mat new_iris = result.layers.eyeball_mask & ~result.layers.sclera_mask;
  cv::erode(new_iris, new_iris, cv::Mat());  // the limbus itself blends into the sclera
  // The photo's glints, moved onto the new irises, are bright by right.
  cv::Mat glints;
  cv::dilate(result.layers.specular > 20, glints, cv::Mat());
  new_iris &= ~glints;
  const auto levels = GreyLevelsByEye(result.image(report.region), new_iris, result.layers.eyeball_mask);
  ASSERT_GT(levels[0].size() + levels[1].size(), 50u);
  const double bright = ShareBeyondHalfway(levels, eyes, /*brighter=*/true);
  std::printf("irises %.0f / %.0f, scleras %.0f / %.0f: %.1f%% of the new irises' pixels brighter than halfway\n",
              eyes[0].iris, eyes[1].iris, eyes[0].sclera, eyes[1].sclera, 100 * bright);
  EXPECT_LT(bright, 0.04);
}

// The converse: the photo's iris that a fit beside it left in its sclera
// used to travel with that sclera, a dark patch beside the new iris (d14.mp4
// frames 433-437, d3.mp4 frame 170). Dark photo sclera from deep in the fitted
// opening (not the lashes' shade at its margin) that the turn moves is
// rendered as sclera now. d30's fit turned 6 degrees either way off the
// photo's irises, then redirected 12 degrees back past them.
TEST(RedirectorTest, AnIrisFittedBesideThePhotosLeavesNoDarkPatchInTheNewSclera) {
  const testing::FittedStill& p = Photo();
  Redirector redirector(SharedModel());
  const std::array<EyeLevels, 2> eyes = PhotoEyeLevels(redirector);
  for (double off : {-6.0, 6.0}) {
    Parameters beside = p.fit.phi;
    beside.gaze_yaw() += off;
    const Redirected result = RedirectPhoto(redirector, beside, Retarget(beside, GazeTarget::Offset(0, -2 * off)));
    ASSERT_TRUE(result.report.redirected[0] && result.report.redirected[1]) << result.report.note;
    cv::Mat new_sclera;
    cv::erode(result.layers.sclera_mask, new_sclera, cv::Mat());
    const auto levels = GreyLevelsByEye(result.image(result.report.region), new_sclera, result.layers.eyeball_mask);
    ASSERT_GT(levels[0].size() + levels[1].size(), 50u);
    const double dark = ShareBeyondHalfway(levels, eyes, /*brighter=*/false);
    std::printf("fit %+.0f deg beside: %.1f%% of the new sclera darker than halfway to the iris\n", off, 100 * dark);
    // 10.5% / 14.8% before session 61 and 1.0% / 2.5% after it (both eyes' levels pooled); 0.0% / 4.8%
    // (4 of 83 pixels) since each eye's colours are matched apart, 4.5% / 10.8% without the drop. Since
    // session 75's refit of d30 0.0% / 6.2% (5 of 81, all in her image-right eye's outer corner along
    // the lower lid, where without the drop more of them lie), 5.7% / 14.8% without the drop.
    EXPECT_LT(dark, 0.09) << off;
  }
}

TEST(RedirectorTest, ClosedEyesAreLeftUntouchedAndReported) {
  const testing::FittedStill& p = Photo();
  Redirector redirector(SharedModel());
  Parameters closed = p.fit.phi;
  closed.eyelid_closure() = 35;
  cv::Mat result = p.image.clone();
  const RedirectReport report = redirector.Redirect(result, p.camera, closed, Retarget(closed, GazeTarget::Offset(0, 20)));
  EXPECT_FALSE(report.redirected[0] || report.redirected[1]);
  EXPECT_NE(report.note.find("closed"), std::string::npos);
  EXPECT_EQ(cv::norm(result, p.image, cv::NORM_INF), 0.0);
}

// A photo of d30 four times larger (her eyes 343 pixels apart, as in a phone's
// portrait) is redirected as the photo itself: shrunk back, the two agree
// but for the working sizes' own differences, and no streaks or hard-edged
// patches of rendered sclera appear. Before the working size, the masks and
// bands tuned on small faces drew both there.
TEST(RedirectorTest, APhotoFourTimesLargerIsRedirectedAsThePhotoItself) {
  const testing::FittedStill& p = Photo();
  constexpr int kTimes = 4;
  cv::Mat large;
  cv::resize(p.image, large, p.image.size() * kTimes, 0, 0, cv::INTER_CUBIC);
  const Camera large_camera = p.camera.Resampled(0, 0, p.image.cols, p.image.rows, large.cols, large.rows);
  const Parameters target = Retarget(p.fit.phi, GazeTarget::Offset(4, -10));
  Redirector redirector(SharedModel());
  cv::Mat small_result = p.image.clone();
  RedirectLayers layers;
  const RedirectReport small_report = redirector.Redirect(small_result, p.camera, p.fit.phi, target, &layers);
  ASSERT_TRUE(small_report.redirected[0] && small_report.redirected[1]) << small_report.note;
  cv::Mat eyes;  // the new eye openings and a pixel around them
  cv::dilate(layers.eyeball_mask, eyes, cv::Mat());

  auto redirect_large = [&](double working_interocular_px) {
    Redirector large_redirector(SharedModel(), {.working_interocular_px = working_interocular_px});
    cv::Mat result = large.clone();
    const RedirectReport report = large_redirector.Redirect(result, large_camera, p.fit.phi, target);
    EXPECT_TRUE(report.redirected[0] && report.redirected[1]) << report.note;
    cv::Mat outside(large.size(), CV_8UC1, cv::Scalar(255));
    outside(report.region).setTo(0);
    EXPECT_EQ(cv::norm(result, large, cv::NORM_INF, outside), 0.0);
    cv::Mat shrunk, difference;
    cv::resize(result, shrunk, p.image.size(), 0, 0, cv::INTER_AREA);
    cv::absdiff(shrunk(small_report.region), small_result(small_report.region), difference);
    std::vector<cv::Mat> channels;
    cv::split(difference, channels);
    const cv::Mat largest = cv::max(cv::max(channels[0], channels[1]), channels[2]);
    const double off = cv::countNonZero((largest > 40) & eyes) / static_cast<double>(cv::countNonZero(eyes));
    const double mean = cv::mean(largest, eyes)[0];
    std::printf("working size %.0f px: in the eyes a mean difference of %.2f levels, %.1f%% of pixels off by more than 40\n",
                working_interocular_px, mean, 100 * off);
    return std::make_pair(mean, off);
  };
  const auto [mean, off] = redirect_large(RedirectOptions().working_interocular_px);
  // The working sizes differ (85.7 and 150 px), and an iris edge a pixel
  // apart differs by far more than 40 levels: 8.8 levels and 2.7% now (10.8
  // and 4.6% before reused sclera was relit, session 64).
  EXPECT_LT(mean, 15);
  EXPECT_LT(off, 0.1);
  // The whole redirection at the large size: 10.4 levels, 4.3% (16.2 and
  // 14.3% before the relighting).
  const auto [mean_at_size, off_at_size] = redirect_large(1e9);
  EXPECT_GT(off_at_size, 1.3 * off);
}

TEST(RedirectorTest, TheEyelidWarpFollowsTheGaze) {
  const testing::FittedStill& p = Photo();
  Redirector redirector(SharedModel());
  const RedirectLayers layers =
      RedirectPhoto(redirector, p.fit.phi, Retarget(p.fit.phi, GazeTarget::Offset(-15, 0))).layers;
  // Looking down lowers the upper lids: their skin comes from above (negative y flow... the
  // source lies above the output pixel), so the mean vertical flow over the skin is negative.
  double flow_y = 0;
  int count = 0;
  for (int y = 0; y < layers.flow.rows; ++y) {
    for (int x = 0; x < layers.flow.cols; ++x) {
      const float f = layers.flow.at<cv::Vec2f>(y, x)[1];
      if (layers.skin_mask.at<uchar>(y, x) && std::abs(f) > 0.3f) flow_y += f, ++count;
    }
  }
  ASSERT_GT(count, 20);
  EXPECT_LT(flow_y / count, -0.3);
}


// Frames 100, 180 and 330 of d3.mp4 with its face tracked from the start, as
// `redirect` fits a video (the iris and sclera colours settle on the open
// eyes of its first frames), once per test binary.
struct FittedFrame {
  cv::Mat image;
  Camera camera;
  FitResult fit;
};
const std::map<int, FittedFrame>& TrackedD3Frames() {
  static const std::map<int, FittedFrame> frames = [] {
    const std::set<int> wanted = {100, 180, 330};
    GazeTracker tracker(SharedModel(), testing::SharedLandmarkDetector(), testing::SharedMeanFace());
    VideoReader reader(testing::DataPath("video/d3.mp4"));
    const Camera camera = Camera::Default(reader.info().width, reader.info().height);
    std::map<int, FittedFrame> tracked;
    cv::Mat image;
    for (int i = 0; i <= *wanted.rbegin() && reader.Read(image); ++i) {
      const std::vector<FaceFit> fits = tracker.ProcessFrame(image, reader.timestamp_s(), camera);
      if (wanted.count(i) == 0) continue;
      EXPECT_EQ(fits.size(), 1u) << "frame " << i;
      tracked[i] = {image.clone(), camera, fits.empty() ? FitResult{} : fits[0].fit};
    }
    EXPECT_EQ(tracked.size(), wanted.size());
    return tracked;
  }();
  return frames;
}

// Redirects `frame` to the camera with `options`.
// A tracked frame redirected from its fit to `target`.
Redirected RedirectFrame(Redirector& redirector, const FittedFrame& frame, const Parameters& target) {
  Redirected redirected{frame.image.clone(), {}, {}};
  redirected.report = redirector.Redirect(redirected.image, frame.camera, frame.fit.phi, target, &redirected.layers);
  return redirected;
}

Redirected RedirectToCamera(const FittedFrame& frame, const RedirectOptions& options) {
  Redirector redirector(SharedModel(), options);
  return RedirectFrame(redirector, frame, Retarget(frame.fit.phi, GazeTarget::Camera()));
}

// d3.mp4 frame 100 looks down under lowered lids (tracked, it shows 0.5 of
// what its eyes show looking level): the photo shows a slit of lashes.
// Redirected to the camera, the opened eyes used to be that slit's dark
// smear, "sclera" as dark as the iris; they get the rendered eyeball now
// (deeper than the margin band), white sclera around a darker iris. An open
// eye (frame 180) is redirected as before.
TEST(RedirectorTest, EyesLookingDownUnderLoweredLidsGetARenderedEyeball) {
  const auto& frames = TrackedD3Frames();
  ASSERT_EQ(frames.count(100) + frames.count(180), 2u);
  const FittedFrame& down = frames.at(100);
  ASSERT_TRUE(down.fit.good) << down.fit.note;
  RedirectOptions reuse_any;
  reuse_any.slit_fraction = reuse_any.clear_fraction = 0;
  const Redirected before = RedirectToCamera(down, reuse_any);
  const Redirected now = RedirectToCamera(down, {});
  ASSERT_TRUE(now.report.redirected[0] && now.report.redirected[1]) << now.report.note;
  auto tones = [](const Redirected& r) {
    cv::Mat sclera, iris;
    cv::erode(r.layers.sclera_mask, sclera, cv::Mat());
    cv::erode(r.layers.eyeball_mask & ~r.layers.sclera_mask, iris, cv::Mat());
    EXPECT_GT(cv::countNonZero(sclera), 20);
    EXPECT_GT(cv::countNonZero(iris), 20);
    const cv::Mat region = r.image(r.report.region);
    return std::pair(Median(GreyLevels(region, sclera)), Median(GreyLevels(region, iris)));
  };
  const auto [sclera_before, iris_before] = tones(before);
  const auto [sclera_now, iris_now] = tones(now);
  std::printf("frame 100: new sclera %.0f, iris %.0f grey levels (from the slit: %.0f, %.0f)\n", sclera_now, iris_now,
              sclera_before, iris_before);
  EXPECT_GT(sclera_now, 1.5 * sclera_before);
  EXPECT_GT(sclera_now, 1.5 * iris_now);

  const FittedFrame& open = frames.at(180);
  ASSERT_TRUE(open.fit.good) << open.fit.note;
  const Redirected open_before = RedirectToCamera(open, reuse_any);
  const Redirected open_now = RedirectToCamera(open, {});
  EXPECT_EQ(cv::norm(open_now.image, open_before.image, cv::NORM_INF), 0.0);
}


// The iris pixels the new eyeballs show between the re-posed lids.
double VisibleIris(const RedirectLayers& layers) {
  return cv::countNonZero(layers.eyeball_mask & ~layers.sclera_mask);
}

// Columbia's pairs reach 10 degrees up, where the lids follow 0.4 of a turn;
// beyond that the upper lid keeps pace with the iris. Following 0.4 of the
// whole turn, d19.jpg turned 20 degrees up kept 71% of the iris its eyes show
// as fitted, and d3.mp4 frame 100 (looking down) met the camera with no more
// iris than its slit showed, half-lidded (now 88% and 147%; 139% for the
// frame as a still).
TEST(RedirectorTest, OnALargeTurnUpTheUpperLidKeepsPaceWithTheIris) {
  EyelidFollow measured_only;
  measured_only.keep_pace_beyond = false;
  const testing::FittedStill& p = testing::FitStill("images/d19.jpg");
  ASSERT_TRUE(p.fit.good) << p.fit.note;
  Redirector redirector(SharedModel());
  const double at_rest = VisibleIris(RedirectPhoto(redirector, p.fit.phi, p.fit.phi, p).layers);
  ASSERT_GT(at_rest, 100);
  auto up_twenty = [&](const EyelidFollow& follow) {
    const Parameters target = Retarget(p.fit.phi, GazeTarget::Offset(20, 0), follow);
    return VisibleIris(RedirectPhoto(redirector, p.fit.phi, target, p).layers) / at_rest;
  };
  const double keeping_pace = up_twenty({}), lagging = up_twenty(measured_only);
  std::printf("d19 up 20: %.0f%% of the fitted iris shows (lids at 0.4 of the turn: %.0f%%)\n", 100 * keeping_pace,
              100 * lagging);
  EXPECT_GT(keeping_pace, 0.8);
  EXPECT_GT(keeping_pace, lagging + 0.1);

  const FittedFrame& down = TrackedD3Frames().at(100);
  ASSERT_TRUE(down.fit.good) << down.fit.note;
  auto to_camera = [&](const Parameters& target) { return VisibleIris(RedirectFrame(redirector, down, target).layers); };
  const double slit = to_camera(down.fit.phi);
  const double contact = to_camera(Retarget(down.fit.phi, GazeTarget::Camera())) / slit;
  const double contact_lagging = to_camera(Retarget(down.fit.phi, GazeTarget::Camera(), measured_only)) / slit;
  std::printf("d3 frame 100 to the camera: %.0f%% of the iris it shows looking down (lids at 0.4: %.0f%%)\n",
              100 * contact, 100 * contact_lagging);
  EXPECT_GT(contact, 1.2);
  EXPECT_GT(contact, contact_lagging + 0.2);
}

// d3.mp4 frame 330 looks 22 degrees aside; its tracked fit puts each iris
// beside the photo's, over sclera that touches a glint. The glint's bright
// patch ran on into that sclera, which then moved as a glint: a white bar
// across each new iris (eye contact). A patch over 15% of the iris must lie
// in dark iris now.
TEST(RedirectorTest, AGlintBesideScleraUnderTheFittedIrisMovesNoBarOfSclera) {
  const auto& frames = TrackedD3Frames();
  ASSERT_EQ(frames.count(330), 1u);
  const FittedFrame& frame = frames.at(330);
  ASSERT_TRUE(frame.fit.good) << frame.fit.note;
  const Redirected result = RedirectToCamera(frame, {});
  ASSERT_TRUE(result.report.redirected[0] && result.report.redirected[1]) << result.report.note;
  cv::Mat new_iris = result.layers.eyeball_mask & ~result.layers.sclera_mask;
  cv::erode(new_iris, new_iris, cv::Mat());
  const std::vector<double> levels = GreyLevels(result.image(result.report.region), new_iris);
  ASSERT_GT(levels.size(), 100u);
  const double bright = std::count_if(levels.begin(), levels.end(), [](double v) { return v > 110; });
  std::printf("frame 330: %.1f%% of the new irises' pixels brighter than 110 grey levels\n",
              100 * bright / levels.size());
  EXPECT_LT(bright / levels.size(), 0.05);
}

// Pixels of `redirected`'s new irises darker than their 5x5 median by more
// than 25 grey levels: two pixels or more inside the eyeballs and clear of
// pupils of `pupil_size` (of the iris's radius) where `target` puts them,
// magnified by the cornea, and two pixels more (none left out: 0).
int DarkSpecksInTheIrises(const Redirected& redirected, const Camera& camera, const Parameters& target,
                          double pupil_size) {
  const cv::Rect& region = redirected.report.region;
  cv::Mat grey, median, irises;
  cv::cvtColor(redirected.image(region), grey, cv::COLOR_BGR2GRAY);
  cv::medianBlur(grey, median, 5);
  cv::erode(redirected.layers.eyeball_mask, irises, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
  irises &= ~redirected.layers.sclera_mask;
  for (int eye = 0; eye < 2 && pupil_size > 0; ++eye) {
    const Eigen::Vector3d centre = IrisCentre(target, eye);
    const Eigen::Vector2d at = camera.Project(centre) - Eigen::Vector2d(region.x, region.y);
    const double pupil = 1.3 * camera.fx * topology::kLimbusRadiusMm * target.iris_size() * pupil_size / centre.z();
    cv::circle(irises, cv::Point(cvRound(at.x()), cvRound(at.y())), cvRound(pupil + 2), cv::Scalar(0), cv::FILLED);
  }
  cv::Mat specks = (median - grey > 25) & irises;
  return cv::countNonZero(specks);
}

// A photo of ../shared/data fitted as `track` and `redirect` fit a photo,
// once per test binary.
const testing::FittedStill& TrackedStill(const std::string& path) {
  static std::map<std::string, testing::FittedStill> stills;
  auto [at, inserted] = stills.try_emplace(path);
  if (inserted) {
    GazeTracker tracker(SharedModel(), testing::SharedLandmarkDetector(), testing::SharedMeanFace());
    const cv::Mat image = ReadImage(testing::DataPath(path));
    const Camera camera = Camera::Default(image.cols, image.rows);
    const std::vector<FaceFit> fits = tracker.ProcessImage(image, camera);
    EXPECT_EQ(fits.size(), 1u) << path;
    at->second = testing::FittedStill{{image, camera, {}}, fits.empty() ? FitResult{} : fits[0].fit};
  }
  return at->second;
}

// d19.jpg is lit brightly and his pupils are narrow. Until session 67 the
// model's pupil was the eyeball texture's, nearly half the iris: the fit's
// black disc left his iris brighter than the rendering, which the chosen
// environment explained as its highlight there. Taken off the iris, or
// keeping it from being reused (its mirror image brought the pupil's edge),
// that highlight left dark specks and arcs in the turned irises.
TEST(RedirectorTest, NarrowPupilsLeaveNoDarkSpecksInTurnedIrises) {
  constexpr double kHisPupils = 0.25;  // of the iris's radius, measured on the photo: about 0.2
  const testing::FittedStill& d19 = TrackedStill("images/d19.jpg");
  ASSERT_TRUE(d19.fit.good) << d19.fit.note;
  Redirector redirector(SharedModel());
  int specks = 0;
  for (const auto& [pitch, yaw] : {std::pair{0.0, 10.0}, {0.0, -10.0}, {10.0, 0.0}, {-10.0, 0.0}}) {
    Parameters target = d19.fit.phi;
    target.gaze_pitch() += pitch;
    target.gaze_yaw() += yaw;
    const Redirected turned = RedirectPhoto(redirector, d19.fit.phi, target, d19);
    ASSERT_TRUE(turned.report.redirected[0] && turned.report.redirected[1]) << turned.report.note;
    const int these = DarkSpecksInTheIrises(turned, d19.camera, target, kHisPupils);
    std::printf("pitch %+.0f yaw %+.0f: %d dark specks in the irises\n", pitch, yaw, these);
    specks += these;
  }
  EXPECT_LE(specks, 3);
}

// A few pixels of d19.jpg's new irises have no photo sample: their sources
// lay under the fitted eye's modelled highlight, which is not reused. The
// rendering filled them with what its own iris shows there, brown or black
// specks beside the photo's pupil (its pupil lies beside his). Enclosed by
// the photo's iris, they now take the iris around them. Turned to the camera
// and 10 degrees up, down, aside either way, his new irises, pupils and all,
// show 0, 0, 0, 4 and 0 dark specks (the 4 his pupil, drawn a little larger)
// against his own 2; before, 3, 6, 5, 9 and 0.
TEST(RedirectorTest, SmallHolesInTheCarriedIrisTakeTheIrisAroundThem) {
  const testing::FittedStill& d19 = TrackedStill("images/d19.jpg");
  ASSERT_TRUE(d19.fit.good) << d19.fit.note;
  Redirector redirector(SharedModel());
  Redirected his_own = RedirectPhoto(redirector, d19.fit.phi, d19.fit.phi, d19);  // for its layers
  his_own.image = d19.image;
  const int his = DarkSpecksInTheIrises(his_own, d19.camera, d19.fit.phi, 0);
  std::printf("his own irises: %d dark specks\n", his);
  int specks = 0;
  for (const GazeTarget& look : {GazeTarget::Camera(), GazeTarget::Offset(10, 0), GazeTarget::Offset(-10, 0),
                                 GazeTarget::Offset(0, 10), GazeTarget::Offset(0, -10)}) {
    const Parameters target = Retarget(d19.fit.phi, look);
    const Redirected turned = RedirectPhoto(redirector, d19.fit.phi, target, d19);
    ASSERT_TRUE(turned.report.redirected[0] && turned.report.redirected[1]) << turned.report.note;
    const int these = DarkSpecksInTheIrises(turned, d19.camera, target, 0);
    std::printf("%s: %d dark specks in the new irises\n", look.Describe().c_str(), these);
    EXPECT_LE(these, his + 3) << look.Describe();
    specks += these;
  }
  EXPECT_LE(specks, 8);
}

// The median grey level of each eye's iris in `image` (8-bit BGR, the
// redirected region) where `layers` show it, the limbus and glints left out.
std::array<double, 2> IrisLevels(const cv::Mat& image, const RedirectLayers& layers) {
  cv::Mat iris = layers.eyeball_mask & ~layers.sclera_mask, glints;
  cv::erode(iris, iris, cv::Mat());
  cv::dilate(layers.specular > 20, glints, cv::Mat());
  iris &= ~glints;
  const auto grey = GreyLevelsByEye(image, iris, layers.eyeball_mask);
  return {grey[0].size() < 20 ? -1 : Median(grey[0]), grey[1].size() < 20 ? -1 : Median(grey[1])};
}

// d8.jpg wears glasses: his image-left eye lies in the lens's shade, dark
// all over, and his image-right eye is lit, its iris a pale blue-grey. One
// colour match over both eyes took most of that pale iris for sclera (its
// bright-iris threshold fell between the two eyes' irises) and rendered it in
// the colours of both, a darker blue: turned to the camera, 10 degrees up or
// 10 aside, its median grey level was 27, 34 and 30 against his 52. Each eye's
// new iris keeps its own grey now (49, 53, 43).
TEST(RedirectorTest, EachEyesNewIrisKeepsThatEyesColours) {
  const testing::FittedStill& d8 = TrackedStill("images/d8.jpg");
  ASSERT_TRUE(d8.fit.good) << d8.fit.note;
  Redirector redirector(SharedModel());
  const Redirected as_fitted = RedirectPhoto(redirector, d8.fit.phi, d8.fit.phi, d8);
  const std::array<double, 2> his = IrisLevels(d8.image(as_fitted.report.region), as_fitted.layers);
  ASSERT_GT(his[1], his[0] + 15) << "the image-right eye is the lit one";
  for (const GazeTarget& target : {GazeTarget::Camera(), GazeTarget::Offset(10, 0), GazeTarget::Offset(0, -10)}) {
    const Redirected turned = RedirectPhoto(redirector, d8.fit.phi, Retarget(d8.fit.phi, target), d8);
    ASSERT_TRUE(turned.report.redirected[0] && turned.report.redirected[1]) << turned.report.note;
    const std::array<double, 2> now = IrisLevels(turned.image(turned.report.region), turned.layers);
    std::printf("irises %.0f / %.0f grey levels, redirected %.0f / %.0f\n", his[0], his[1], now[0], now[1]);
    for (int side = 0; side < 2; ++side) EXPECT_NEAR(now[side], his[side], 12) << side;
  }
}

// Pixels of each eye's `mask` (MaskByEye of itself) whose red exceeds their
// blue by more than 20 grey levels in `image` (8-bit BGR).
std::array<int, 2> ReddishPixelsByEye(const cv::Mat& image, const cv::Mat& mask) {
  std::vector<cv::Mat> channels;
  cv::split(image, channels);
  cv::Mat red_over_blue;
  cv::subtract(channels[2], channels[0], red_over_blue, cv::noArray(), CV_16S);
  const std::array<cv::Mat, 2> halves = MaskByEye((red_over_blue > 20) & mask, mask);
  return {cv::countNonZero(halves[0]), cv::countNonZero(halves[1])};
}

// Reddish pixels (ReddishPixelsByEye) in d8.jpg's eye in the lens's shade
// (image left): in the photo as fitted, and redirected to each of `targets`.
struct ShadedEyeReds {
  int photo;
  std::vector<int> turned;
};
ShadedEyeReds ShadedEyeReddishPixels(const std::vector<GazeTarget>& targets) {
  const testing::FittedStill& d8 = TrackedStill("images/d8.jpg");
  EXPECT_TRUE(d8.fit.good) << d8.fit.note;
  Redirector redirector(SharedModel());
  const Redirected as_fitted = RedirectPhoto(redirector, d8.fit.phi, d8.fit.phi, d8);
  ShadedEyeReds reds{ReddishPixelsByEye(d8.image(as_fitted.report.region), as_fitted.layers.eyeball_mask)[0], {}};
  for (const GazeTarget& target : targets) {
    const Redirected turned = RedirectPhoto(redirector, d8.fit.phi, Retarget(d8.fit.phi, target), d8);
    EXPECT_TRUE(turned.report.redirected[0] && turned.report.redirected[1]) << turned.report.note;
    reds.turned.push_back(ReddishPixelsByEye(turned.image(turned.report.region), turned.layers.eyeball_mask)[0]);
    std::printf("%s: %d reddish pixels in the shaded eye (the photo: %d)\n", target.Describe().c_str(),
                reds.turned.back(), reds.photo);
  }
  return reds;
}

// In d8.jpg's shaded eye the sclera is darker than his lid's skin, so a spot
// of skin that the fitted eyeball overlaps passed for a glint, and the bright
// patch it lies in, a streak along his lower lid, was moved with the cornea:
// a thin orange line under each new iris. Reddish pixels turned to the
// camera, 10 degrees up and 10 to either side: 19, 28, 11 and 11 (the photo
// 5); 1, 5, 0 and 0 once a glint's light had to have the colour of a light,
// not the skin's (none with each eye's clear sclera, below).
TEST(RedirectorTest, LidSkinInAShadedEyeIsNotMovedAsAGlint) {
  const ShadedEyeReds reds = ShadedEyeReddishPixels(
      {GazeTarget::Camera(), GazeTarget::Offset(10, 0), GazeTarget::Offset(0, 10), GazeTarget::Offset(0, -10)});
  for (int turned : reds.turned) EXPECT_LE(turned, reds.photo + 3);
}

// Turned 20 degrees up, d8.jpg's shaded eye bares sclera above his lower lid
// that the photo did not show; rendered, it took the colour of both eyes'
// clear sclera, his lit eye's pinkish white, where the shaded eye shows none
// nearby: 36 reddish pixels against the photo's 5. Each eye's own clear
// sclera: none.
TEST(RedirectorTest, ScleraRenderedInAShadedEyeTakesThatEyesColour) {
  const ShadedEyeReds reds = ShadedEyeReddishPixels({GazeTarget::Offset(20, 0)});
  ASSERT_EQ(reds.turned.size(), 1u);
  EXPECT_LE(reds.turned[0], reds.photo + 3);
}

}  // namespace
}  // namespace gazedirector
