#include "gazedirector/redirect/glints.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "gazedirector/fit/face_fit.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/model/eye_region_topology.h"
#include "gazedirector/redirect/eye_image.h"

namespace gazedirector {
namespace {

// One fitted eye's pixels in the photo, within a box around them: its
// eyeball, the part of it the fitted cornea covers (the iris), and their
// luminance (in no order).
struct EyePixels {
  cv::Rect box;           // around the eyeball with a margin of half its height, in the photo
  cv::Mat eyeball, iris;  // 8-bit masks of the box's size
  std::vector<double> iris_luminance, sclera_luminance;
};

// Both fitted eyes' pixels (indexed by Eye) in `photo`.
std::array<EyePixels, 2> PixelsOfEyes(const cv::Mat& photo, const RenderBuffers& fitted, const cv::Mat& cornea) {
  const int width = photo.cols;
  std::array<cv::Rect, 2> boxes;
  for (int pixel : fitted.foreground) {
    const int part = fitted.PartAt(pixel);
    if (IsEyeball(part)) boxes[EyeOfPart(part)] |= cv::Rect(pixel % width, pixel / width, 1, 1);
  }
  std::array<EyePixels, 2> eyes;
  for (int eye = 0; eye < 2; ++eye) {
    const int margin = std::max(4, boxes[eye].height / 2);
    const cv::Rect box = GrownWithin(boxes[eye], margin, photo.size());
    eyes[eye].box = box;
    eyes[eye].eyeball = cv::Mat(box.size(), CV_8UC1, cv::Scalar(0));
    eyes[eye].iris = cv::Mat(box.size(), CV_8UC1, cv::Scalar(0));
  }
  for (int pixel : fitted.foreground) {
    const int part = fitted.PartAt(pixel);
    if (!IsEyeball(part)) continue;
    EyePixels& eye = eyes[EyeOfPart(part)];
    const int x = pixel % width, y = pixel / width;
    const bool sclera = IsSclera(cornea, x, y);
    eye.eyeball.at<uchar>(y - eye.box.y, x - eye.box.x) = 255;
    if (!sclera) eye.iris.at<uchar>(y - eye.box.y, x - eye.box.x) = 255;
    (sclera ? eye.sclera_luminance : eye.iris_luminance).push_back(Luminance(photo.at<cv::Vec3f>(y, x)));
  }
  return eyes;
}

// The `q` quantile of `values` (not empty), the lower of the two around it;
// reorders them.
double LowerQuantile(std::vector<double>& values, double q) {
  const auto nth = values.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), nth, values.end());
  return *nth;
}

// What tells one eye's glints from the rest of it (luminance).
struct GlintLevels {
  float brightest_sclera;  // a glint's peak outshines this (the sclera's 98th percentile)
  float sclera;            // the sclera's median
  float bright;            // its pixels outshine this (the sclera's 90th percentile, or halfway from iris to sclera)
  float dark_surround;     // most pixels around it are darker: iris
  float stands_out;        // its spot stands out of its surroundings (white top-hat) by this
  float rim;               // its rim, by this
  int wide;                // the top-hat's width in pixels: wider than the largest glint
};

GlintLevels LevelsOfGlints(EyePixels& eye, double largest) {
  const float iris = static_cast<float>(LowerQuantile(eye.iris_luminance, 0.5));
  const float sclera = static_cast<float>(LowerQuantile(eye.sclera_luminance, 0.5));
  const float contrast = std::max(0.2f, sclera - iris);
  GlintLevels levels;
  levels.brightest_sclera = static_cast<float>(LowerQuantile(eye.sclera_luminance, 0.98));
  levels.sclera = sclera;
  levels.bright = std::max(static_cast<float>(LowerQuantile(eye.sclera_luminance, 0.9)), iris + 0.5f * contrast);
  levels.dark_surround = iris + 0.3f * contrast;
  levels.stands_out = 0.3f * contrast;
  levels.rim = 0.1f * contrast;
  const double radius = std::sqrt(largest * static_cast<double>(eye.iris_luminance.size()) / M_PI);
  levels.wide = 2 * static_cast<int>(2 * radius) + 3;
  return levels;
}

// Whether the light that `area` adds over the eye `around` it is tinted like
// the skin beside the eye (`skin`) more than it is grey. A glint has the
// colour of the light it reflects, near white in a balanced photo; lid skin
// that a fitted eyeball overlaps has the skin's (d8.jpg's eye in his lens's
// shade, whose sclera is darker than his lid: an orange streak along the lid
// was moved as a glint).
bool TintedLikeSkin(const cv::Mat& eye_photo, const cv::Mat& area, const cv::Mat& around, const cv::Vec3f& skin) {
  if (cv::countNonZero(around) == 0) return false;
  const cv::Rect box = cv::boundingRect(area | around);  // the ring encloses the area
  const cv::Scalar mean = cv::mean(eye_photo(box), area(box));
  const cv::Vec3f light = cv::Vec3f(static_cast<float>(mean[0]), static_cast<float>(mean[1]), static_cast<float>(mean[2])) -
                          MedianColour(eye_photo(box), around(box));
  auto chromaticity = [](const cv::Vec3f& colour) {
    const float sum = colour[0] + colour[1] + colour[2];
    return sum > 1e-4f ? cv::Vec3f(colour / sum) : cv::Vec3f::all(1.0f / 3);
  };
  const cv::Vec3f tint = chromaticity(light);
  return cv::norm(tint - chromaticity(skin), cv::NORM_L1) < cv::norm(tint - cv::Vec3f::all(1.0f / 3), cv::NORM_L1);
}

// The cores of one eye's glints: spots on the fitted iris that stand out of
// their surroundings, lie mostly off its outermost pixels and are mostly
// surrounded by dark iris (the sclera beside an iris the fit missed by a
// little is neither). A spot whose peak
// outshines all of the sclera brings the whole bright patch it lies in, on
// the iris or just beside it; a small one (at most 3% of the iris, as
// compressed video leaves a glint) is a glint if it is brighter than the
// sclera's median and stands 0.15 above its surroundings. Neither may add
// light tinted like the skin beside the eye (TintedLikeSkin).
cv::Mat GlintCores(const EyePixels& eye, const GlintLevels& levels, const cv::Mat& eye_photo, const cv::Mat& luminance,
                   const cv::Mat& tophat) {
  constexpr double kSmallShare = 0.03, kSmallContrast = 0.15, kLargeShare = 0.15;
  const cv::Mat around = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5));
  const cv::Mat beyond_halo = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(7, 7));
  cv::Mat cores(luminance.size(), CV_8UC1, cv::Scalar(0));
  const cv::Mat spots = eye.iris & (tophat > std::max(static_cast<double>(levels.stands_out), kSmallContrast));
  if (cv::countNonZero(spots) == 0) return cores;
  cv::Mat spot_labels, spot_stats, centroids;
  const int spot_count = cv::connectedComponentsWithStats(spots, spot_labels, spot_stats, centroids, 8, CV_32S);
  // The bright patches near the iris, labelled once a spot needs them.
  cv::Mat patch_labels, patch_stats;
  auto label_patches = [&] {
    if (!patch_labels.empty()) return;
    cv::Mat near_iris;
    cv::dilate(eye.iris, near_iris, around);
    cv::connectedComponentsWithStats(near_iris & eye.eyeball & (luminance > levels.bright), patch_labels, patch_stats,
                                     centroids, 8, CV_32S);
  };
  const int small = std::max(2, static_cast<int>(kSmallShare * static_cast<double>(eye.iris_luminance.size())));
  // One labelled area within the box that holds it and its ring (`box`).
  // Worked on in the box alone: a spot is a few pixels of an eye's box.
  struct Area {
    cv::Rect box;
    cv::Mat mask;
  };
  auto area_of = [&](const cv::Mat& labels, const cv::Mat& stats, int label) {
    const cv::Rect bounds(stats.at<int>(label, cv::CC_STAT_LEFT), stats.at<int>(label, cv::CC_STAT_TOP),
                          stats.at<int>(label, cv::CC_STAT_WIDTH), stats.at<int>(label, cv::CC_STAT_HEIGHT));
    const cv::Rect box = GrownWithin(bounds, beyond_halo.cols / 2, labels.size());
    return Area{box, labels(box) == label};
  };
  // The ring two to three pixels out of `area` on the eyeball, beyond a
  // glint's own halo (in the area's box).
  auto ring_of = [&](const Area& area) {
    cv::Mat ring, halo;
    cv::dilate(area.mask, ring, beyond_halo);
    cv::dilate(area.mask, halo, around);
    return cv::Mat(ring & eye.eyeball(area.box) & ~halo);
  };
  std::optional<cv::Vec3f> skin;  // the skin beside the eye, once a candidate needs it
  auto tinted_like_skin = [&](const Area& area, const cv::Mat& ring) {
    if (!skin) skin = MedianColour(eye_photo, ~eye.eyeball);
    return TintedLikeSkin(eye_photo(area.box), area.mask, ring, *skin);
  };
  // Light along the fitted iris's outermost pixels is the photo's sclera
  // that a fitted iris a pixel beside the photo's covers (Columbia 0004's
  // left eye: moved as a glint, a thin bright crescent across the new sclera).
  cv::Mat inner_iris;
  cv::erode(eye.iris, inner_iris, cv::Mat());
  const cv::Mat iris_edge = eye.iris & ~inner_iris;
  for (int label = 1; label < spot_count; ++label) {
    const Area spot = area_of(spot_labels, spot_stats, label);
    const int spot_pixels = spot_stats.at<int>(label, cv::CC_STAT_AREA);
    if (2 * cv::countNonZero(spot.mask & iris_edge(spot.box)) > spot_pixels) continue;
    double peak = 0;
    cv::Point brightest;
    cv::minMaxLoc(luminance(spot.box), nullptr, &peak, nullptr, &brightest, spot.mask);
    const cv::Mat spot_ring = ring_of(spot);
    const double surround = MedianUnder(luminance(spot.box), spot_ring, -1);
    if (surround < 0 || surround > levels.dark_surround) continue;
    if (peak > levels.brightest_sclera && peak > levels.bright) {
      // A large patch (over kLargeShare of the iris) must lie in dark iris
      // too: one that runs on into the sclera which a fitted iris beside the
      // photo's covers (d3.mp4 frame 330) would move that sclera as a glint,
      // a white bar across the new iris.
      label_patches();
      const int patch_label = patch_labels.at<int>(brightest + spot.box.tl());
      const Area patch = area_of(patch_labels, patch_stats, patch_label);
      const cv::Mat patch_ring = ring_of(patch);
      const int patch_pixels = patch_stats.at<int>(patch_label, cv::CC_STAT_AREA);
      if (patch_pixels > kLargeShare * static_cast<double>(eye.iris_luminance.size())) {
        const double patch_surround = MedianUnder(luminance(patch.box), patch_ring, -1);
        if (patch_surround < 0 || patch_surround > levels.dark_surround) continue;
      }
      if (!tinted_like_skin(patch, patch_ring)) cores(patch.box) |= patch.mask;
    } else if (spot_pixels <= small && peak > levels.sclera && peak - surround > kSmallContrast &&
               !tinted_like_skin(spot, spot_ring)) {
      cores(spot.box) |= spot.mask;
    }
  }
  return cores;
}

}  // namespace

// The glints of the photo's eyes as fitted (`fitted`, with its cornea
// attribute `cornea`): their cores (GlintCores) and their rims on the iris,
// up to two pixels around where they stand out a little. What a glint adds
// is the photo over the eye filled in beneath it, from the iris around it
// (and, beside the iris, from the sclera around it): left where it was,
// the two give back the photo.
Glints FindGlints(const cv::Mat& photo, const RenderBuffers& fitted, const cv::Mat& cornea) {
  constexpr std::size_t kEnough = 10;  // samples of iris and of sclera
  constexpr double kLargest = 0.25;    // of the iris: larger bright patches are no glints (glasses, a window)
  Glints glints;
  std::array<EyePixels, 2> eyes = PixelsOfEyes(photo, fitted, cornea);
  for (int eye = 0; eye < 2; ++eye) {
    EyePixels& pixels = eyes[eye];
    if (pixels.iris_luminance.size() < kEnough || pixels.sclera_luminance.size() < kEnough) continue;
    const double iris_pixels = static_cast<double>(pixels.iris_luminance.size());
    const GlintLevels levels = LevelsOfGlints(pixels, kLargest);
    const cv::Mat eye_photo = photo(pixels.box);
    cv::Mat eye_luminance, tophat;
    cv::transform(eye_photo, eye_luminance, cv::Matx13f(0.114f, 0.587f, 0.299f));
    cv::morphologyEx(eye_luminance, tophat, cv::MORPH_TOPHAT,
                     cv::getStructuringElement(cv::MORPH_RECT, cv::Size(levels.wide, levels.wide)));
    const cv::Mat cores = GlintCores(pixels, levels, eye_photo, eye_luminance, tophat);
    const int core_pixels = cv::countNonZero(cores);
    if (core_pixels == 0 || core_pixels > kLargest * iris_pixels) continue;
    cv::Mat glint;
    cv::dilate(cores, glint, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
    glint = cores | (glint & pixels.iris & (tophat > levels.rim));
    // Beneath a glint and a pixel around it: the iris around it, or the
    // sclera where it reaches beside the iris; never brighter than the photo
    // (a glint only adds light: a dark limbus beside it stays).
    cv::Mat fill;
    cv::dilate(glint, fill, cv::Mat());
    fill &= pixels.eyeball;
    if (glints.surface.empty()) {
      glints.surface = photo.clone();
      glints.filled = cv::Mat(photo.size(), CV_8UC1, cv::Scalar(0));
    }
    // Within reach of the glints only.
    const double reach = std::max(1.5, 0.25 * std::sqrt(iris_pixels / M_PI));
    const int margin = static_cast<int>(std::ceil(3 * reach)) + 1;
    const cv::Rect area = cv::boundingRect(fill);
    const cv::Rect near = GrownWithin(area, margin, fill.size());
    const cv::Mat iris = pixels.iris(near), sclera = pixels.eyeball(near) & ~iris, near_photo = eye_photo(near);
    const cv::Mat unfilled = ~fill(near);
    const cv::Rect within = area - near.tl();
    const cv::Mat near_iris = iris & unfilled, near_sclera = sclera & unfilled;
    cv::Mat beneath = NearbyColour(near_photo, near_iris, within, reach, MedianColour(near_photo, near_iris));
    NearbyColour(near_photo, near_sclera, within, reach, MedianColour(near_photo, near_sclera)).copyTo(beneath, sclera);
    cv::min(beneath, near_photo, beneath);
    const cv::Rect in_photo = near + pixels.box.tl();
    cv::Mat near_surface = glints.surface(in_photo), near_filled = glints.filled(in_photo);
    beneath.copyTo(near_surface, fill(near));
    near_filled |= fill(near);
    glints.found[eye] = true;
  }
  if (!glints.surface.empty()) {
    glints.light = cv::Mat(photo.size(), CV_32FC3, cv::Scalar::all(0));
    cv::subtract(photo, glints.surface, glints.light, glints.filled);
  }
  return glints;
}

std::array<cv::Vec2f, 2> GlintShifts(const Parameters& fitted, const Parameters& target, const Camera& camera) {
  const std::array<EyeGaze, 2> from = EyeGazes(fitted), to = EyeGazes(target);
  auto cornea_centre = [&camera](const EyeGaze& eye) {
    return camera.Project(eye.centre + topology::kCorneaCentreMm * eye.gaze);
  };
  std::array<cv::Vec2f, 2> shifts;
  for (int eye = 0; eye < 2; ++eye) {
    const Eigen::Vector2d shift = cornea_centre(to[eye]) - cornea_centre(from[eye]);
    shifts[eye] = {static_cast<float>(shift.x()), static_cast<float>(shift.y())};
  }
  return shifts;
}

cv::Mat MovedGlints(const Glints& glints, const std::array<cv::Vec2f, 2>& shifts, const RenderBuffers& target) {
  cv::Mat moved(glints.light.size(), CV_32FC3, cv::Scalar::all(0));
  const int width = moved.cols;
  for (int pixel : target.foreground) {
    const int part = target.PartAt(pixel);
    if (!IsEyeball(part) || !glints.found[EyeOfPart(part)]) continue;
    const int x = pixel % width, y = pixel / width;
    const cv::Vec2f& shift = shifts[EyeOfPart(part)];
    moved.at<cv::Vec3f>(y, x) = Bilinear(glints.light, x - shift[0], y - shift[1]);
  }
  return moved;
}

}  // namespace gazedirector
