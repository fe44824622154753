#include "gazedirector/redirect/eyeball_transfer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "gazedirector/redirect/eye_image.h"

namespace gazedirector {
namespace {

// The largest hole in the carried iris filled from the iris around it, as a share of its eye's iris.
constexpr float kMostIrisHole = 0.05f;

// Reused sclera takes the model's change of shading from where it was to
// where it is, within this range: more light is allowed less, since the
// model's lid shadow is only a rough guess and photo sclera brightened
// past its clearest parts reads as a white patch. Fit renderings darker than
// kDarkestRelit (luminance) say too little to divide by.
constexpr std::array<float, 2> kRelightRange = {0.6f, 1.1f};
constexpr float kDarkestRelit = 0.02f;

// What reused sclera is multiplied by where the re-posed model renders it
// at luminance `here` and the fit rendered it at `there`.
float RelightFactor(float here, float there) {
  return there > kDarkestRelit ? std::clamp(here / there, kRelightRange[0], kRelightRange[1]) : 1.0f;
}

// The pixel a sub-pixel position falls in.
cv::Point NearestPixel(const cv::Vec2f& position) {
  return {static_cast<int>(std::lround(position[0])), static_cast<int>(std::lround(position[1]))};
}

}  // namespace

EyeballTransfer TransferEyeballs(const RenderBuffers& fitted, const RenderBuffers& target, const TransferInputs& in,
                                 bool reuse_photo, bool keep_sources) {
  const int width = target.width(), height = target.height();
  EyeballTransfer transfer(cv::Size(width, height), keep_sources);
  for (std::size_t i = 0; i < target.foreground.size(); ++i) {
    const int pixel = target.foreground[i];
    const int part = target.PartAt(pixel);
    if (!IsEyeball(part)) continue;
    const int x = pixel % width, y = pixel / width;
    const cv::Vec3f colour = RenderedBgr(target, i);
    transfer.rendered.at<cv::Vec3f>(y, x) = colour;
    if (!reuse_photo) continue;
    // An eye under lowered lids shows a slit of lashes: it gives the new
    // lid margins their shade but neither the eyeball deeper in nor the
    // rendering's colours.
    const float slit_share = in.target_depth.at<float>(y, x) > in.margin_px ? in.slit[EyeOfPart(part)] : 0.0f;
    if (slit_share >= 1) continue;
    // The photo where this surface point was, else where its mirror images were.
    // (The iris is dark itself: there the lashes' shade does no harm.)
    const bool sclera = IsSclera(in.cornea, x, y);
    const float depth_needed = sclera ? std::min(in.target_depth.at<float>(y, x), in.margin_px) - 0.5f : -1.0f;
    auto usable = [&](const cv::Vec2f& s) {
      const cv::Point at = NearestPixel(s);
      if (!cv::Rect(0, 0, width, height).contains(at)) return false;
      if (fitted.PartAt(at.y * width + at.x) != part) return false;
      if (in.source_depth.at<float>(at) < depth_needed) return false;  // lash shade
      return !(in.gain > 0 && in.gain * Luminance(in.old_specular.at<cv::Vec3f>(at)) > kHighlight);  // an old highlight
    };
    cv::Vec2f s = in.source.at<cv::Vec2f>(y, x);
    bool found = usable(s);
    // Within the margin band only the mirror image across the vertical plane
    // serves: it stays under the same lid, whose lashes shade it alike. One
    // across the horizontal plane brings the other lid's light (s42.jpg
    // turned aside: a dotted bright line under her upper lashes).
    const bool in_margin = in.target_depth.at<float>(y, x) < in.margin_px;
    const cv::Vec6f& mirrors = in.mirror_source.at<cv::Vec6f>(y, x);
    for (int k = 0; k < (in_margin ? 1 : 3) && !found; ++k) {
      s = {mirrors[2 * k], mirrors[2 * k + 1]};
      found = usable(s);
    }
    if (!found) continue;
    // Sclera is lit as the model lights it here, not where it was: lid
    // shadow moves with the lids, and a mirror image was on the other side of
    // the eyeball (s42.jpg turned aside: her bright temporal sclera drew
    // light streaks in the shade of her nasal sclera).
    const float relight = sclera ? RelightFactor(Luminance(colour), in.fitted_luminance.at<float>(NearestPixel(s)))
                                 : 1.0f;
    // The photo's surface without the faint reflections the chosen
    // environment explains there: the re-posed eye gets its own.
    cv::Vec3f value = Bilinear(in.surface, s[0], s[1]);
    if (in.gain > 0) {
      // A sample beside a strong highlight, which is not reused, would
      // take off part of it: no more than a faint one (d19.jpg: dark specks
      // in the iris around its modelled highlight).
      cv::Vec3f old_highlight = static_cast<float>(in.gain) * Bilinear(in.old_specular, s[0], s[1]);
      const float strength = Luminance(old_highlight);
      if (strength > kHighlight) old_highlight *= kHighlight / strength;
      for (int c = 0; c < 3; ++c) value[c] = std::max(0.0f, value[c] - old_highlight[c]);
      if (keep_sources) transfer.highlight.at<cv::Vec3f>(y, x) = old_highlight;
    }
    value *= relight;
    transfer.transferred.at<cv::Vec3f>(y, x) = value;
    if (keep_sources) {
      transfer.source.at<cv::Vec2f>(y, x) = s;
      transfer.relit_by.at<float>(y, x) = relight;
    }
    if (sclera) transfer.from_depth.at<float>(y, x) = in.source_depth.at<float>(NearestPixel(s));
    transfer.moved_by.at<float>(y, x) = std::hypot(s[0] - x, s[1] - y);
    transfer.transfer_mask.data[pixel] = cv::saturate_cast<uchar>(255 * (1 - slit_share));
    if (in.slit[EyeOfPart(part)] < 0.5f) transfer.colours.Add(EyeOfPart(part), value, colour, sclera);
  }
  transfer.colours.Finish();
  return transfer;
}


cv::Mat DropMisleadingTransfers(EyeballTransfer& transfer, const RenderBuffers& target, const cv::Mat& cornea,
                                const cv::Mat& target_depth, float margin_px) {
  cv::Mat clear_sclera(transfer.transfer_mask.size(), CV_8UC1, cv::Scalar(0));
  const int width = transfer.transfer_mask.cols;
  for (int pixel : target.foreground) {
    const int x = pixel % width, y = pixel / width;
    if (!transfer.transfer_mask.data[pixel]) continue;
    const EyeColourMatch& colours = transfer.colours[EyeOfPart(target.PartAt(pixel))];
    if (!IsSclera(cornea, x, y)) {
      if (colours.bright_iris() > 0 && transfer.moved_by.at<float>(y, x) > margin_px &&
          Luminance(transfer.transferred.at<cv::Vec3f>(y, x)) > colours.bright_iris()) {
        transfer.transfer_mask.data[pixel] = 0;
      }
      continue;
    }
    if (Luminance(transfer.transferred.at<cv::Vec3f>(y, x)) >= colours.dark_sclera()) {
      clear_sclera.data[pixel] = 255;
    } else if (target_depth.at<float>(y, x) > margin_px &&
               target_depth.at<float>(y, x) > transfer.from_depth.at<float>(y, x) + margin_px) {
      transfer.transfer_mask.data[pixel] = 0;
    } else if (transfer.from_depth.at<float>(y, x) > margin_px && transfer.moved_by.at<float>(y, x) > margin_px) {
      transfer.transfer_mask.data[pixel] = 0;  // the photo's iris, left in the fitted sclera, would travel with it
    }
  }
  return clear_sclera;
}


cv::Point NearestCarried(const cv::Mat& carried, const cv::Point& at, int reach) {
  const cv::Rect image(0, 0, carried.cols, carried.rows);
  cv::Point nearest = at;
  int best = std::numeric_limits<int>::max();
  for (int radius = 1; radius <= reach; ++radius) {
    // A pixel on this square ring is at least `radius` away.
    if (best <= radius * radius) break;
    for (int dy = -radius; dy <= radius; ++dy) {
      const int step = std::abs(dy) == radius ? 1 : 2 * radius;
      for (int dx = -radius; dx <= radius; dx += step) {
        const cv::Point p(at.x + dx, at.y + dy);
        if (!image.contains(p) || !carried.at<uchar>(p) || dx * dx + dy * dy >= best) continue;
        best = dx * dx + dy * dy;
        nearest = p;
      }
    }
  }
  return nearest;
}


void FillIrisHoles(EyeballTransfer& transfer, const RenderBuffers& target, const cv::Mat& cornea) {
  const cv::Size size = transfer.transfer_mask.size();
  cv::Mat holes(size, CV_8UC1, cv::Scalar(0)), carried(size, CV_8UC1, cv::Scalar(0));  // iris pixels
  std::array<int, 2> iris_pixels = {0, 0};
  for (int pixel : target.foreground) {
    const int part = target.PartAt(pixel);
    if (!IsEyeball(part) || IsSclera(cornea, pixel % size.width, pixel / size.width)) continue;
    ++iris_pixels[EyeOfPart(part)];
    if (transfer.transfer_mask.data[pixel] == 255) carried.data[pixel] = 255;
    if (transfer.transfer_mask.data[pixel] == 0) holes.data[pixel] = 255;
  }
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(holes, labels, stats, centroids, 8, CV_32S);
  const cv::Rect image(0, 0, size.width, size.height);
  for (int label = 1; label < count; ++label) {
    const cv::Rect box(stats.at<int>(label, cv::CC_STAT_LEFT), stats.at<int>(label, cv::CC_STAT_TOP),
                       stats.at<int>(label, cv::CC_STAT_WIDTH), stats.at<int>(label, cv::CC_STAT_HEIGHT));
    // Its pixels, and whether anything but carried iris borders them (the
    // scan stops at the first row that shows it does).
    std::vector<cv::Point> pixels;
    bool enclosed = true;
    for (int y = box.y; y < box.br().y && enclosed; ++y) {
      for (int x = box.x; x < box.br().x; ++x) {
        if (labels.at<int>(y, x) != label) continue;
        pixels.emplace_back(x, y);
        for (const cv::Point& step : {cv::Point(1, 0), cv::Point(-1, 0), cv::Point(0, 1), cv::Point(0, -1)}) {
          const cv::Point next(x + step.x, y + step.y);
          if (!image.contains(next) || (labels.at<int>(next) != label && !carried.at<uchar>(next))) enclosed = false;
        }
      }
    }
    const int eye = EyeOfPart(target.PartAt(pixels.front().y * size.width + pixels.front().x));
    if (!enclosed || pixels.size() > kMostIrisHole * iris_pixels[eye]) continue;
    for (const cv::Point& at : pixels) {
      const cv::Point from = NearestCarried(carried, at, box.width + box.height);
      transfer.transferred.at<cv::Vec3f>(at) = transfer.transferred.at<cv::Vec3f>(from);
      transfer.transfer_mask.at<uchar>(at) = 255;
      if (!transfer.source.empty()) {
        transfer.source.at<cv::Vec2f>(at) = transfer.source.at<cv::Vec2f>(from);
        transfer.highlight.at<cv::Vec3f>(at) = transfer.highlight.at<cv::Vec3f>(from);
        transfer.relit_by.at<float>(at) = transfer.relit_by.at<float>(from);
      }
    }
  }
}

}  // namespace gazedirector
