#include "gazedirector/redirect/composite_recipe.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "gazedirector/redirect/eye_image.h"

namespace gazedirector {
namespace {

// The four recipe pixels around a point and their bilinear weights.
struct Neighbours {
  std::array<cv::Point, 4> at;
  std::array<float, 4> weight;
};

Neighbours Around(float x, float y, cv::Size size) {
  x = std::clamp(x, 0.0f, size.width - 1.0f), y = std::clamp(y, 0.0f, size.height - 1.0f);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, size.width - 1), y1 = std::min(y0 + 1, size.height - 1);
  const float fx = x - x0, fy = y - y0;
  return {{cv::Point(x0, y0), cv::Point(x1, y0), cv::Point(x0, y1), cv::Point(x1, y1)},
          {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy}};
}

// The bilinear blend of `image` over those neighbours where `use` holds,
// renormalised: values across a mask's edge belong to another surface and
// must not be mixed in. False when no neighbour with weight qualifies.
template <typename T, typename Use>
bool Blend(const cv::Mat& image, const Neighbours& around, Use use, T& out) {
  T sum = T();
  float total = 0;
  for (int k = 0; k < 4; ++k) {
    if (around.weight[k] <= 0 || !use(around.at[k])) continue;
    sum += around.weight[k] * image.at<T>(around.at[k]);
    total += around.weight[k];
  }
  if (total <= 0) return false;
  out = sum * (1.0f / total);
  return true;
}

// Where `p` fetches from by the blend of its neighbours' fetches (`sources`,
// CV_32FC2) where `use` holds: their offsets are blended, not their
// positions, so that a region's edge and a mask's do not pull it aside.
template <typename Use>
bool BlendFetch(const cv::Mat& sources, const Neighbours& around, cv::Point2f p, Use use, cv::Vec2f& out) {
  cv::Vec2f offset(0, 0);
  float total = 0;
  for (int k = 0; k < 4; ++k) {
    if (around.weight[k] <= 0 || !use(around.at[k])) continue;
    const cv::Point q = around.at[k];
    offset += around.weight[k] * (sources.at<cv::Vec2f>(q) - cv::Vec2f(q.x, q.y));
    total += around.weight[k];
  }
  if (total <= 0) return false;
  out = cv::Vec2f(p.x, p.y) + offset * (1.0f / total);
  return true;
}

}  // namespace

cv::Mat FollowRecipe(const CompositeRecipe& recipe, const cv::Mat& photo, double scale_x, double scale_y,
                     const cv::Mat& eyeball_mask, double seam) {
  const cv::Rect& region = recipe.region;
  // Photo pixel <-> recipe pixel, as cv::resize maps pixel centres.
  auto to_recipe = [&](int x, int y) {
    return cv::Point2f(static_cast<float>((x + 0.5) / scale_x - 0.5 - region.x),
                       static_cast<float>((y + 0.5) / scale_y - 0.5 - region.y));
  };
  auto to_photo = [&](const cv::Vec2f& p) {
    return cv::Point2f(static_cast<float>((p[0] + region.x + 0.5) * scale_x - 0.5),
                       static_cast<float>((p[1] + region.y + 0.5) * scale_y - 0.5));
  };
  auto sample = [&](const cv::Vec2f& p) {
    const cv::Point2f at = to_photo(p);
    return Bilinear(photo, at.x, at.y);
  };
  // The glint-filled surface: the photo's own pixels except where its glints were filled.
  auto surface_at = [&](const cv::Vec2f& p) {
    cv::Vec3f value = sample(p);
    if (recipe.glint_fill.empty()) return value;
    const Neighbours around = Around(p[0], p[1], region.size());
    float fill = 0;
    Blend(recipe.glint_fill, around, [](cv::Point) { return true; }, fill);
    return fill > 0 ? (1 - fill) * value + fill * Bilinear(recipe.surface, p[0], p[1]) : value;
  };
  auto eyeball = [&](cv::Point q) { return recipe.eyeball_mask.at<uchar>(q) != 0; };
  auto skin_or_outside = [&](cv::Point q) { return recipe.eyeball_mask.at<uchar>(q) == 0; };
  auto shared = [&](cv::Point q) { return recipe.photo_share.at<float>(q) > 0; };

  cv::Mat out = photo.clone();
  cv::Mat eyeballs(photo.size(), CV_8UC1, cv::Scalar(0));  // where this size's new eyeballs are
  cv::Mat glints = recipe.glints.empty() ? cv::Mat() : cv::Mat(photo.size(), CV_32FC3, cv::Scalar::all(0));
  const int x_begin = std::max(0, static_cast<int>(std::ceil(region.x * scale_x - 0.5)));
  const int x_end = std::min(photo.cols, static_cast<int>(std::floor((region.x + region.width) * scale_x - 0.5)) + 1);
  const int y_begin = std::max(0, static_cast<int>(std::ceil(region.y * scale_y - 0.5)));
  const int y_end = std::min(photo.rows, static_cast<int>(std::floor((region.y + region.height) * scale_y - 0.5)) + 1);
  for (int y = y_begin; y < y_end; ++y) {
    for (int x = x_begin; x < x_end; ++x) {
      const cv::Point2f p = to_recipe(x, y);
      const Neighbours around = Around(p.x, p.y, region.size());
      float coverage = 0;
      for (int k = 0; k < 4; ++k) coverage += eyeball(around.at[k]) ? around.weight[k] : 0.0f;
      cv::Vec3f warped = photo.at<cv::Vec3f>(y, x);
      cv::Vec2f fetch;
      const bool fetched = BlendFetch(recipe.skin_source, around, p, skin_or_outside, fetch);
      if (fetched) warped = sample(fetch);
      // An eyeball pixel needs a recipe eyeball pixel beside it, and a skin
      // pixel a skin one: else it takes what its neighbours are.
      const bool in_eyeball = eyeball_mask.empty() ? coverage >= 0.5f
                                                   : (eyeball_mask.at<uchar>(y, x) ? coverage > 0 : !fetched);
      if (!in_eyeball) {
        out.at<cv::Vec3f>(y, x) = warped;
        continue;
      }
      float alpha = 0, share = 0;
      cv::Vec3f colour;
      Blend(recipe.seam_alpha, around, eyeball, alpha);
      Blend(recipe.photo_share, around, eyeball, share);
      Blend(recipe.rest, around, eyeball, colour);
      cv::Vec2f source;
      cv::Vec3f highlight;
      if (share > 0 && BlendFetch(recipe.photo_source, around, p, shared, source)) {
        Blend(recipe.highlight, around, shared, highlight);
        float gain = 1;
        if (!recipe.photo_gain.empty()) Blend(recipe.photo_gain, around, shared, gain);
        const cv::Vec3f value = gain * (surface_at(source) - highlight);
        colour += share * cv::Vec3f(std::max(0.0f, value[0]), std::max(0.0f, value[1]), std::max(0.0f, value[2]));
      }
      out.at<cv::Vec3f>(y, x) = alpha * colour + (1 - alpha) * warped;
      eyeballs.at<uchar>(y, x) = 255;
      if (!glints.empty()) Blend(recipe.glints, around, eyeball, glints.at<cv::Vec3f>(y, x));
    }
  }
  // As at the working size: the seam softened, then the glints added.
  if (seam > 0) BlurSeam(out, eyeballs, cv::boundingRect(eyeballs), seam);
  if (!glints.empty()) out += glints;
  return out;
}

}  // namespace gazedirector
