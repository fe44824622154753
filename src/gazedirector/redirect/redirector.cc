#include "gazedirector/redirect/redirector.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "gazedirector/redirect/eye_colour_match.h"
#include "gazedirector/redirect/eye_image.h"
#include "gazedirector/redirect/eyeball_transfer.h"
#include "gazedirector/redirect/glints.h"
#include "gazedirector/render/limbus_distance.h"
#include "gazedirector/render/model_bounds.h"

namespace gazedirector {

// The photo's highlights on the fitted eyes, and what stands in for them on
// the new ones.
struct Highlights {
  int environment = -1;  // the environment map chosen
  double gain = 0;       // of its reflections (none: 0)
  cv::Mat old_specular;  // its reflections on the fitted eyes, before the gain (none where glints were filled in)
  cv::Mat new_specular;  // and on the new ones, faint only where the photo's glints move
  Glints glints;         // the photo's own glints, filled in
  cv::Mat moved_glints;  // what they add, moved with the corneas (empty if none)

  // All that is added to the new eyeballs (CV_32FC3; empty if nothing).
  cv::Mat Added() const {
    cv::Mat added = gain > 0 ? cv::Mat(new_specular * gain) : cv::Mat();
    if (!moved_glints.empty()) added = added.empty() ? moved_glints : cv::Mat(added + moved_glints);
    return added;
  }
};

namespace {

// The cornea's reflectance at normal incidence (water-like, n = 1.376).
constexpr float kFresnel = 0.028f;

// Projections of every posed vertex of `parts` into `camera`: the rasterized
// attribute that says where a surface point was in the photo.
void ProjectParts(const PosedModel& posed, const Camera& camera, std::array<bool, kNumParts> parts,
                  std::array<Eigen::MatrixXf, kNumParts>& out) {
  for (int part = 0; part < kNumParts; ++part) {
    if (!parts[part]) {
      out[part].resize(0, 0);
      continue;
    }
    const Eigen::Matrix3Xf& p = posed.parts[part].positions;
    out[part].resize(2, p.cols());
    for (Eigen::Index v = 0; v < p.cols(); ++v) {
      const float z = std::max(p(2, v), 1.0f);
      out[part](0, v) = static_cast<float>(camera.fx) * p(0, v) / z + static_cast<float>(camera.cx);
      out[part](1, v) = static_cast<float>(camera.fy) * p(1, v) / z + static_cast<float>(camera.cy);
    }
  }
}

// For each eyeball part, the columns of `sources` permuted to the vertices'
// mirror images across x, across z and across both (six rows).
void MirrorEyeballSources(const std::array<Eigen::MatrixXf, kNumParts>& sources, const EyeballModel& eyeball,
                          std::array<Eigen::MatrixXf, kNumParts>& mirrors) {
  const std::vector<int>& across_x = eyeball.mirrored_across_x();
  const std::vector<int>& across_z = eyeball.mirrored_across_z();
  for (int part = 0; part < kNumParts; ++part) {
    if (!IsEyeball(part) || sources[part].cols() != static_cast<Eigen::Index>(across_x.size())) {
      mirrors[part].resize(0, 0);
      continue;
    }
    mirrors[part].resize(6, sources[part].cols());
    for (Eigen::Index v = 0; v < sources[part].cols(); ++v) {
      mirrors[part].block<2, 1>(0, v) = sources[part].col(across_x[v]);
      mirrors[part].block<2, 1>(2, v) = sources[part].col(across_z[v]);
      mirrors[part].block<2, 1>(4, v) = sources[part].col(across_z[across_x[v]]);
    }
  }
}

int CountPart(const RenderBuffers& buffers, int part) {
  int count = 0;
  for (int pixel : buffers.foreground) count += buffers.PartAt(pixel) == part;
  return count;
}

// The luminance of `buffers`' rendering (CV_32F, 0 off the foreground).
cv::Mat RenderedLuminance(const RenderBuffers& buffers) {
  cv::Mat luminance(buffers.height(), buffers.width(), CV_32F, cv::Scalar(0));
  for (std::size_t i = 0; i < buffers.foreground.size(); ++i) {
    luminance.at<float>(buffers.foreground[i] / buffers.width(), buffers.foreground[i] % buffers.width()) =
        Luminance(RenderedBgr(buffers, i));
  }
  return luminance;
}

// The eyelid warp over the eye region: every pixel's source in the photo
// (itself, except where the re-posed model's facial skin fetches the photo
// where its surface was), and the masks of that skin and of the new eyeballs.
struct EyelidWarp {
  cv::Mat map;           // CV_32FC2
  cv::Mat skin_mask;     // 8-bit
  cv::Mat eyeball_mask;  // 8-bit
};

EyelidWarp WarpFromModel(const RenderBuffers& target, const cv::Mat& source, bool warp_eyelids) {
  const cv::Size size = source.size();
  EyelidWarp warp;
  warp.map.create(size, CV_32FC2);
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) warp.map.at<cv::Vec2f>(y, x) = {static_cast<float>(x), static_cast<float>(y)};
  }
  warp.skin_mask = cv::Mat(size, CV_8UC1, cv::Scalar(0));
  warp.eyeball_mask = cv::Mat(size, CV_8UC1, cv::Scalar(0));
  for (int pixel : target.foreground) {
    const int part = target.PartAt(pixel);
    if (IsEyeball(part)) {
      warp.eyeball_mask.data[pixel] = 255;
    } else if (warp_eyelids) {
      const int y = pixel / size.width, x = pixel % size.width;
      warp.map.at<cv::Vec2f>(y, x) = source.at<cv::Vec2f>(y, x);
      warp.skin_mask.data[pixel] = 255;
    }
  }
  return warp;
}

// Caps `specular` at a luminance of `most` on the eyeballs of `target`: the
// photo's own glints, moved, stand in for the strong reflections (where it
// shows none, rendered ones would add sparkle the photo did not have).
void KeepFaintReflections(cv::Mat& specular, const RenderBuffers& target, float most) {
  const int width = specular.cols;
  for (int pixel : target.foreground) {
    if (!IsEyeball(target.PartAt(pixel))) continue;
    cv::Vec3f& value = specular.at<cv::Vec3f>(pixel / width, pixel % width);
    const float luminance = Luminance(value);
    if (luminance > most) value *= most / luminance;
  }
}

// The photo's clear sclera as the fit showed it, per pixel of the new
// eyeballs (`target`) its own eye's: the median colour of the brighter half of
// that eye's fitted sclera deeper than `margin_px` inside the fitted opening
// (lids, lashes and the iris's edge are darker), or that eye's colour match's
// sclera where fewer than ten pixels show (elsewhere both eyes'). It is what
// rendered sclera takes where the photo shows none nearby: both eyes' clear
// sclera gave d8.jpg's eye in the shade of his glasses his lit eye's pinkish
// white above its lower lid.
cv::Mat ClearScleraOfEachEye(const cv::Mat& photo, const RenderBuffers& fitted, const cv::Mat& fitted_cornea,
                             const cv::Mat& source_depth, float margin_px, const RenderBuffers& target,
                             const EyeColourMatches& colours) {
  std::array<cv::Mat, 2> clear_masks = {cv::Mat(photo.size(), CV_8UC1, cv::Scalar(0)),
                                        cv::Mat(photo.size(), CV_8UC1, cv::Scalar(0))};
  for (int pixel : fitted.foreground) {
    const int x = pixel % photo.cols, y = pixel / photo.cols;
    const int part = fitted.PartAt(pixel);
    if (IsEyeball(part) && IsSclera(fitted_cornea, x, y) && source_depth.at<float>(y, x) > margin_px) {
      clear_masks[EyeOfPart(part)].data[pixel] = 255;
    }
  }
  cv::Mat luminance;
  cv::cvtColor(photo, luminance, cv::COLOR_BGR2GRAY);  // Luminance()'s weights
  std::array<cv::Vec3f, 2> clear;
  for (int eye = 0; eye < 2; ++eye) {
    cv::Mat& mask = clear_masks[eye];
    if (cv::countNonZero(mask) < 10) {
      clear[eye] = colours[eye].sclera_colour();
      continue;
    }
    mask &= luminance >= MedianUnder(luminance, mask, 0);
    clear[eye] = MedianColour(photo, mask);
  }
  cv::Mat typical(photo.size(), CV_32FC3, cv::Scalar(colours.both().sclera_colour()));
  for (int pixel : target.foreground) {
    const int part = target.PartAt(pixel);
    if (IsEyeball(part)) typical.at<cv::Vec3f>(pixel / photo.cols, pixel % photo.cols) = clear[EyeOfPart(part)];
  }
  return typical;
}

// What --debug-dir shows of one redirection; `specular`: the reflections
// added (CV_32FC3), empty where none were.
RedirectLayers DebugLayers(const EyelidWarp& warp, const EyeballTransfer& transfer, const cv::Mat& cornea,
                           const cv::Mat& eyeball_layer, const cv::Mat& specular) {
  RedirectLayers layers;
  const cv::Size size = warp.map.size();
  layers.flow.create(size, CV_32FC2);
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      const cv::Vec2f s = warp.map.at<cv::Vec2f>(y, x);
      layers.flow.at<cv::Vec2f>(y, x) = {s[0] - x, s[1] - y};
    }
  }
  layers.skin_mask = warp.skin_mask;
  layers.eyeball_mask = warp.eyeball_mask;
  layers.transfer_mask = transfer.transfer_mask;
  layers.sclera_mask = warp.eyeball_mask & (cornea < kLimbus);
  eyeball_layer.convertTo(layers.eyeball_layer, CV_8UC3, 255.0);
  if (specular.empty()) {
    layers.specular = cv::Mat(size, CV_8UC1, cv::Scalar(0));
  } else {
    cv::Mat grey;
    cv::cvtColor(specular, grey, cv::COLOR_BGR2GRAY);
    grey.convertTo(layers.specular, CV_8U, 255.0);
  }
  return layers;
}

// The rendering's colours matched to the photo's, each eye's to its own
// (sclera: as the photo's sclera nearby, `photo_sclera`), over the new
// eyeballs (`target`; `eyeball_mask` is their mask). The match switches from
// the iris's colours to the sclera's at the rendered iris's edge
// (`limbus_distance`), which a per-pixel choice alone would draw as steps:
// it is antialiased.
cv::Mat MatchedRendering(const EyeballTransfer& transfer, const RenderBuffers& target, const cv::Mat& eyeball_mask,
                         const cv::Mat& limbus_distance, const cv::Mat& photo_sclera) {
  cv::Mat matched(eyeball_mask.size(), CV_32FC3, cv::Scalar::all(0));
  const int width = matched.cols;
  for (int pixel : target.foreground) {
    const int part = target.PartAt(pixel);
    if (!IsEyeball(part)) continue;
    const int x = pixel % width, y = pixel / width;
    const EyeColourMatch& colours = transfer.colours[EyeOfPart(part)];
    const bool sclera = limbus_distance.at<float>(y, x) > 0;
    const cv::Vec3f nearby_sclera = sclera && colours.sclera_known() ? photo_sclera.at<cv::Vec3f>(y, x) : cv::Vec3f();
    matched.at<cv::Vec3f>(y, x) = colours.Match(transfer.rendered.at<cv::Vec3f>(y, x), sclera, nearby_sclera);
  }
  return MixedAcrossEdge(matched, eyeball_mask, limbus_distance);
}

// The new eyeballs over the warped photo: the photo's share (`transfer`)
// feathered into the matched rendering (`matched`) and reflections added
// (`gain` x `specular`); where the mask is thinner than about `seam` pixels
// (the corners) the warped photo shows through. The photo's share is
// blurred by `feather` within the eyeball mask (normalised), so that the
// mask's own edge, where the photo continues outside, does not fade into the
// rendering. `eyeball_layer` gets the eyeballs' colours before the seam;
// `recipe` (when given) how each was made.
cv::Mat CompositeEyeballs(const cv::Mat& warped, const cv::Mat& eyeball_mask, const cv::Rect& eyeballs_area,
                          const EyeballTransfer& transfer, const cv::Mat& matched, double gain,
                          const cv::Mat& specular, double feather, double seam, cv::Mat& eyeball_layer,
                          CompositeRecipe* recipe) {
  cv::Mat transfer_weight, eyeball_weight, eyeball_share, seam_alpha;
  transfer.transfer_mask.convertTo(transfer_weight, CV_32F, 1.0 / 255);
  eyeball_mask.convertTo(eyeball_weight, CV_32F, 1.0 / 255);
  transfer_weight = BlurredWithin(transfer_weight, eyeballs_area, feather);
  eyeball_share = BlurredWithin(eyeball_weight, eyeballs_area, feather);
  transfer_weight /= cv::max(eyeball_share, 1e-3f);
  seam_alpha = BlurredWithin(eyeball_weight, eyeballs_area, seam);

  eyeball_layer = warped.clone();
  cv::Mat out = warped.clone();
  if (recipe != nullptr) {
    recipe->photo_share = cv::Mat(warped.size(), CV_32F, cv::Scalar(0));
    recipe->rest = cv::Mat(warped.size(), CV_32FC3, cv::Scalar::all(0));
    recipe->seam_alpha = cv::Mat(warped.size(), CV_32F, cv::Scalar(0));
  }
  for (int y = 0; y < warped.rows; ++y) {
    for (int x = 0; x < warped.cols; ++x) {
      if (!eyeball_mask.at<uchar>(y, x)) continue;
      const float w = transfer.transfer_mask.at<uchar>(y, x) ? transfer_weight.at<float>(y, x) : 0.0f;
      const cv::Vec3f photo_part = w * transfer.transferred.at<cv::Vec3f>(y, x);
      cv::Vec3f colour = photo_part + (1 - w) * matched.at<cv::Vec3f>(y, x);
      if (gain > 0) colour += static_cast<float>(gain) * specular.at<cv::Vec3f>(y, x);
      eyeball_layer.at<cv::Vec3f>(y, x) = colour;
      const float a = std::min(1.0f, 2.0f * seam_alpha.at<float>(y, x));
      out.at<cv::Vec3f>(y, x) = a * colour + (1 - a) * warped.at<cv::Vec3f>(y, x);
      if (recipe != nullptr) {
        recipe->photo_share.at<float>(y, x) = w;
        recipe->rest.at<cv::Vec3f>(y, x) = colour - photo_part;
        recipe->seam_alpha.at<float>(y, x) = a;
      }
    }
  }
  return out;
}

// 1 (CV_32F) where the glints were filled (8-bit `filled`), and a pixel
// around: a larger photo's glints have edges beyond the working size's.
cv::Mat GlintFill(const cv::Mat& filled) {
  cv::Mat fill;
  cv::dilate(filled, fill, cv::Mat());
  fill.convertTo(fill, CV_32F, 1.0 / 255);
  return fill;
}

// Writes into `recipe` how each pixel of `region` was made.
void FillRecipe(const cv::Rect& region, const EyelidWarp& warp, const EyeballTransfer& transfer,
                const Highlights& highlights, CompositeRecipe& recipe) {
  recipe.region = region;
  recipe.skin_source = warp.map;
  recipe.eyeball_mask = warp.eyeball_mask;
  recipe.photo_source = transfer.source;
  recipe.highlight = transfer.highlight;
  recipe.photo_gain = transfer.relit_by;
  recipe.glints = highlights.moved_glints;
  if (!highlights.glints.surface.empty()) {
    recipe.surface = highlights.glints.surface;
    recipe.glint_fill = GlintFill(highlights.glints.filled);
  }
}

// `rect` of an image resized by `scale_x` x `scale_y`: the pixels it covers there.
cv::Rect Enlarged(const cv::Rect& rect, double scale_x, double scale_y) {
  const cv::Point top_left(static_cast<int>(std::floor(rect.x * scale_x)),
                           static_cast<int>(std::floor(rect.y * scale_y)));
  const cv::Point bottom_right(static_cast<int>(std::ceil(rect.br().x * scale_x)),
                               static_cast<int>(std::ceil(rect.br().y * scale_y)));
  return {top_left, bottom_right};
}

}  // namespace

cv::Mat FlowPicture(const cv::Mat& flow, double scale) {
  cv::Mat hsv(flow.size(), CV_8UC3);
  for (int y = 0; y < flow.rows; ++y) {
    for (int x = 0; x < flow.cols; ++x) {
      const cv::Vec2f f = flow.at<cv::Vec2f>(y, x);
      const double angle = std::atan2(f[1], f[0]) * 180 / M_PI;
      const double length = std::hypot(f[0], f[1]);
      hsv.at<cv::Vec3b>(y, x) = {cv::saturate_cast<uchar>((angle < 0 ? angle + 360 : angle) / 2),
                                 cv::saturate_cast<uchar>(255 * std::min(1.0, length / scale)), 255};
    }
  }
  cv::Mat bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  return bgr;
}

Redirector::Redirector(std::shared_ptr<const EyeRegionModel> model, RedirectOptions options)
    : model_(model),
      options_(options),
      fitted_renderer_(model),
      target_renderer_(model),
      cornea_flags_(Renderer::CorneaAttribute(*model)) {}

Parameters Redirector::PosedTarget(const Parameters& fitted, const Parameters& target) const {
  Parameters posed = target;
  if (!options_.warp_eyelids) {  // the lids stay as fitted
    posed.eyelid_pitch() = fitted.eyelid_pitch();
    posed.eyelid_closure() = fitted.eyelid_closure();
  }
  return posed;
}

std::array<int, 2> Redirector::EyeballPixels(const Parameters& phi, const Camera& crop) {
  target_renderer_.set_eyes(true, true);
  target_renderer_.Pose(phi);
  const cv::Rect bounds = EyeballBounds(target_renderer_.posed(), crop);
  if (bounds.empty()) return {0, 0};
  // Only the eyeballs' bounds are rasterized: all their pixels lie there.
  target_renderer_.Rasterize(crop.Cropped(bounds.x, bounds.y, bounds.width, bounds.height), target_buffers_);
  return {CountPart(target_buffers_, kLeftEyeball), CountPart(target_buffers_, kRightEyeball)};
}

std::array<bool, 2> Redirector::OpenEyes(const Parameters& fitted, const Camera& crop, std::string& note) {
  // How much eyeball the fit (in fitted_buffers_) shows, against the same
  // eyes with their lids at rest.
  Parameters rested = fitted;
  rested.eyelid_closure() = 0;
  rested.eyelid_pitch() = fitted.gaze_pitch();
  const std::array<int, 2> at_rest = EyeballPixels(rested, crop);
  std::array<bool, 2> open = {true, true};
  for (int eye = 0; eye < 2; ++eye) {
    const int rest = at_rest[eye];
    const int shown = CountPart(fitted_buffers_, EyeballPart(eye));
    const char* side = eye == kLeftEye ? "left" : "right";
    if (rest < 6) {
      open[eye] = false;
      note += fmt::format("{}{} eye too small to redirect ({} pixels of eyeball)", note.empty() ? "" : "; ", side, rest);
    } else if (shown < options_.min_open_fraction * rest) {
      open[eye] = false;
      note += fmt::format("{}{} eye closed or hidden ({:.0f}% of its eyeball shows)", note.empty() ? "" : "; ", side,
                          100.0 * shown / rest);
    }
  }
  return open;
}

std::array<float, 2> Redirector::SlitShares(const Parameters& fitted, const Camera& crop) {
  std::array<float, 2> slit = {0, 0};
  if (!options_.transfer_eyeballs || options_.slit_fraction >= options_.clear_fraction) return slit;
  // The same eyes looking level with their lids at rest.
  Parameters level = fitted;
  level.gaze_pitch() = 0;
  level.eyelid_pitch() = 0;
  level.eyelid_closure() = 0;
  const std::array<int, 2> at_rest = EyeballPixels(level, crop);
  for (int eye = 0; eye < 2; ++eye) {
    const int rest = at_rest[eye];
    const double shown = rest > 0 ? static_cast<double>(CountPart(fitted_buffers_, EyeballPart(eye))) / rest : 0;
    slit[eye] = static_cast<float>(std::clamp(
        (options_.clear_fraction - shown) / (options_.clear_fraction - options_.slit_fraction), 0.0, 1.0));
  }
  return slit;
}

void Redirector::Reflections(const Renderer& renderer, const RenderBuffers& buffers, const Camera& camera,
                             const EnvironmentMap& map, cv::Mat& specular) const {
  specular.create(buffers.height(), buffers.width(), CV_32FC3);
  specular.setTo(cv::Scalar::all(0));
  std::array<Eigen::MatrixXf, kNumParts> normals;
  for (int part : {kLeftEyeball, kRightEyeball}) normals[part] = renderer.posed().parts[part].normals;
  const cv::Mat field = Renderer::InterpolateAttribute(buffers, *model_, normals, 3);
  for (int pixel : buffers.foreground) {
    if (!IsEyeball(buffers.PartAt(pixel))) continue;
    const int x = pixel % buffers.width(), y = pixel / buffers.width();
    const cv::Vec3f n_cv = field.at<cv::Vec3f>(y, x);
    const Eigen::Vector3f n = Eigen::Vector3f(n_cv[0], n_cv[1], n_cv[2]).normalized();
    const Eigen::Vector3f view = camera.Ray(Eigen::Vector2d(x, y)).cast<float>();
    const float cosine = std::max(0.0f, -view.dot(n));
    const Eigen::Vector3f reflected = view - 2 * view.dot(n) * n;
    const float fresnel = kFresnel + (1 - kFresnel) * std::pow(1 - cosine, 5.0f);
    const Eigen::Vector3f rgb = fresnel * map.Radiance(reflected);
    specular.at<cv::Vec3f>(y, x) = {rgb.z(), rgb.y(), rgb.x()};
  }
}

int Redirector::ChooseEnvironment(const cv::Mat& photo, const Camera& camera, int fixed, double& gain,
                                  cv::Mat& specular) {
  const auto& maps = BuiltInEnvironmentMaps();
  const int first = fixed >= 0 ? fixed : 0, last = fixed >= 0 ? fixed : static_cast<int>(maps.size()) - 1;
  gain = 0;
  // Bright residuals of the photo over the fitted eyeballs: the highlights
  // the diffuse model cannot explain.
  std::vector<int> pixels;
  std::vector<float> residual;
  for (std::size_t i = 0; i < fitted_buffers_.foreground.size(); ++i) {
    const int pixel = fitted_buffers_.foreground[i];
    if (!IsEyeball(fitted_buffers_.PartAt(pixel))) continue;
    const cv::Vec3f observed = photo.at<cv::Vec3f>(pixel / photo.cols, pixel % photo.cols);
    pixels.push_back(pixel);
    residual.push_back(std::max(0.0f, Luminance(observed) - Luminance(RenderedBgr(fitted_buffers_, i))));
  }
  if (pixels.size() < 10) return first;
  double baseline = 0;
  for (float r : residual) baseline += r * r;
  int best = first;
  double best_error = baseline;
  cv::Mat candidate;
  for (int k = first; k <= last; ++k) {
    Reflections(fitted_renderer_, fitted_buffers_, camera, maps[k], candidate);
    double hh = 0, hr = 0;
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      const float h = Luminance(candidate.at<cv::Vec3f>(pixels[i] / photo.cols, pixels[i] % photo.cols));
      hh += h * h, hr += h * residual[i];
    }
    if (hh <= 0) continue;
    const double a = std::clamp(hr / hh, 0.0, 3.0);
    const double error = baseline - 2 * a * hr + a * a * hh;
    if (error < best_error) {
      best_error = error, best = k, gain = a;
      std::swap(specular, candidate);
    }
  }
  // Reflections that explain too little are not worth adding.
  if (best_error > 0.97 * baseline) gain = 0;
  // They count only as far as the photo shows light there: the model places
  // a highlight only roughly, and one placed on plain iris would be taken off
  // it (dark specks) or keep it from being reused (d19.jpg: its mirror image
  // brought the pupil's edge into the iris).
  for (std::size_t i = 0; gain > 0 && i < pixels.size(); ++i) {
    cv::Vec3f& value = specular.at<cv::Vec3f>(pixels[i] / photo.cols, pixels[i] % photo.cols);
    const float modelled = static_cast<float>(gain) * Luminance(value);
    if (modelled > residual[i]) value *= residual[i] / modelled;
  }
  return best;
}

RedirectReport Redirector::Redirect(cv::Mat& image, const Camera& camera, const Parameters& fitted,
                                    const Parameters& target, RedirectLayers* layers) {
  const double interocular_px = camera.fx * fitted.interocular() / std::max(1.0, fitted.translation().z());
  const double scale = interocular_px / std::max(1.0, options_.working_interocular_px);
  if (scale <= 1) return RedirectAtThisSize(image, camera, fitted, target, layers, nullptr);
  return RedirectShrunk(image, camera, fitted, target, scale, layers);
}

RedirectReport Redirector::RedirectShrunk(cv::Mat& image, const Camera& camera, const Parameters& fitted,
                                          const Parameters& target, double scale, RedirectLayers* layers) {
  // The eye region with room for the working size's own margins and blurs.
  fitted_renderer_.set_eyes(true, true);
  fitted_renderer_.Pose(fitted);
  target_renderer_.set_eyes(true, true);
  target_renderer_.Pose(PosedTarget(fitted, target));
  const cv::Rect area = (ModelBounds(fitted_renderer_.posed(), camera, 0.1) |
                         ModelBounds(target_renderer_.posed(), camera, 0.1)) & cv::Rect(0, 0, image.cols, image.rows);
  const cv::Size small_size(std::max(1, static_cast<int>(std::lround(area.width / scale))),
                            std::max(1, static_cast<int>(std::lround(area.height / scale))));
  if (area.empty() || small_size.width < 8 || small_size.height < 4) {
    RedirectReport report;
    report.note = "the eyes are outside the image";
    return report;
  }
  cv::Mat small;
  cv::resize(image(area), small, small_size, 0, 0, cv::INTER_AREA);
  const Camera small_camera = camera.Resampled(area.x, area.y, area.width, area.height, small.cols, small.rows);
  CompositeRecipe recipe;
  RedirectReport report = RedirectAtThisSize(small, small_camera, fitted, target, layers, &recipe);
  if (!report.redirected[0] && !report.redirected[1]) return report;
  // The new eyeballs' outline at full size, where the recipe's would step.
  const Camera area_camera = camera.Cropped(area.x, area.y, area.width, area.height);
  target_renderer_.set_eyes(report.redirected[0], report.redirected[1]);
  target_renderer_.Pose(PosedTarget(fitted, target));
  target_renderer_.Rasterize(area_camera, target_buffers_);

  const double scale_x = static_cast<double>(area.width) / small.cols;
  const double scale_y = static_cast<double>(area.height) / small.rows;
  cv::Mat photo;
  image(area).convertTo(photo, CV_32FC3, 1.0 / 255);
  const double seam = std::max(0.5, options_.seam_blur * options_.working_interocular_px * scale);
  FollowRecipe(recipe, photo, scale_x, scale_y, target_buffers_.EyeballMaskImage(), seam)
      .convertTo(image(area), CV_8UC3, 255.0);
  report.region = (Enlarged(report.region, scale_x, scale_y) + area.tl()) & cv::Rect(0, 0, image.cols, image.rows);
  return report;
}

RedirectReport Redirector::RedirectAtThisSize(cv::Mat& image, const Camera& camera, const Parameters& fitted,
                                              const Parameters& target, RedirectLayers* layers,
                                              CompositeRecipe* recipe) {
  RedirectReport report;
  const Parameters posed_target = PosedTarget(fitted, target);
  const std::optional<EyeRegionView> view = RenderBoth(image.size(), camera, fitted, posed_target, report.note);
  if (!view) return report;
  const cv::Rect& region = view->region;
  const Camera& crop_camera = view->camera;
  const std::array<bool, 2>& eyes = view->eyes;
  const std::array<float, 2>& slit = view->slit;
  cv::Mat photo;
  image(region).convertTo(photo, CV_32FC3, 1.0 / 255);

  // Where each surface point of the re-posed model was in the photo.
  ProjectParts(fitted_renderer_.posed(), crop_camera, {options_.warp_eyelids, options_.warp_eyelids, true, true}, sources_);
  const cv::Mat source = Renderer::InterpolateAttribute(target_buffers_, *model_, sources_, 2);
  // And where its mirror images across the eyeball's vertical and horizontal
  // planes were: stand-ins for eyeball surface the photo did not show.
  MirrorEyeballSources(sources_, model_->eyeball(), mirrors_);
  const cv::Mat mirror_source = Renderer::InterpolateAttribute(target_buffers_, *model_, mirrors_, 6);

  // The eyelid warp: facial skin pixels fetch the photo where their surface was.
  const EyelidWarp warp = WarpFromModel(target_buffers_, source, options_.warp_eyelids);
  const cv::Mat& eyeball_mask = warp.eyeball_mask;
  cv::Mat warped;
  cv::remap(photo, warped, warp.map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);

  const cv::Mat fitted_cornea = Renderer::InterpolateAttribute(fitted_buffers_, *model_, cornea_flags_, 1);
  const Highlights highlights = FindHighlights(photo, crop_camera, fitted, posed_target, fitted_cornea);
  report.environment = highlights.environment;
  report.specular_gain = highlights.gain;

  // The new eyeballs; the moved glints come on their own.
  const cv::Mat& surface = highlights.glints.surface.empty() ? photo : highlights.glints.surface;
  const cv::Mat cornea = Renderer::InterpolateAttribute(target_buffers_, *model_, cornea_flags_, 1);
  // How deep inside its eye opening each pixel is (pixels from the lids), in
  // the photo's fit and in the re-posed model. Surface the photo showed at
  // its lid margin carries the lashes' shade: it may land near the new
  // margin, not deep in the new opening, where it would draw dark streaks.
  const cv::Mat source_depth = DepthInside(fitted_buffers_.EyeballMaskImage());
  const cv::Mat target_depth = DepthInside(eyeball_mask);
  const double interocular_px = crop_camera.fx * fitted.interocular() / std::max(1.0, fitted.translation().z());
  const float margin_px = static_cast<float>(std::max(1.5, options_.margin_band * interocular_px));
  const cv::Mat fitted_luminance = RenderedLuminance(fitted_buffers_);
  EyeballTransfer transfer = TransferEyeballs(
      fitted_buffers_, target_buffers_,
      {surface, source, mirror_source, cornea, source_depth, target_depth, margin_px, highlights.gain,
       highlights.old_specular, slit, fitted_luminance},
      options_.transfer_eyeballs, recipe != nullptr);
  const cv::Mat clear_sclera = DropMisleadingTransfers(transfer, target_buffers_, cornea, target_depth, margin_px);
  FillIrisHoles(transfer, target_buffers_, cornea);
  const cv::Rect eyeballs_area = cv::boundingRect(eyeball_mask);
  const cv::Mat photo_sclera =
      transfer.colours.both().sclera_known()
          ? NearbyColour(transfer.transferred, clear_sclera, eyeballs_area,
                         std::max(1.0, options_.sclera_colour_reach * interocular_px),
                         ClearScleraOfEachEye(photo, fitted_buffers_, fitted_cornea, source_depth, margin_px,
                                              target_buffers_, transfer.colours))
          : cv::Mat();
  const double feather = std::max(0.8, options_.transfer_feather * interocular_px);
  const double seam = std::max(0.5, options_.seam_blur * interocular_px);
  const cv::Mat limbus_distance = LimbusDistance(target_buffers_, *model_, target_renderer_.posed());
  const cv::Mat matched = MatchedRendering(transfer, target_buffers_, eyeball_mask, limbus_distance, photo_sclera);
  cv::Mat eyeball_layer;
  cv::Mat out = CompositeEyeballs(warped, eyeball_mask, eyeballs_area, transfer, matched, highlights.gain,
                                  highlights.new_specular, feather, seam, eyeball_layer, recipe);
  // The seam is softened, then the glints are added, so that it does not
  // smear those next to the lids. (A recipe is followed at full size first.)
  if (recipe == nullptr) BlurSeam(out, eyeball_mask, eyeballs_area, seam);
  if (!highlights.moved_glints.empty()) {
    if (recipe == nullptr) out += highlights.moved_glints;
    eyeball_layer += highlights.moved_glints;
  }
  out.convertTo(image(region), CV_8UC3, 255.0);
  report.redirected = eyes;
  report.region = region;
  if (recipe != nullptr) FillRecipe(region, warp, transfer, highlights, *recipe);
  if (layers != nullptr) *layers = DebugLayers(warp, transfer, cornea, eyeball_layer, highlights.Added());
  return report;
}

std::optional<Redirector::EyeRegionView> Redirector::RenderBoth(const cv::Size& image_size, const Camera& camera,
                                                                const Parameters& fitted,
                                                                const Parameters& posed_target, std::string& note) {
  if (fitted.eyelid_closure() > options_.max_closure_deg) {
    note = fmt::format("eyes closed (lid closure {:.0f} deg)", fitted.eyelid_closure());
    return std::nullopt;
  }
  fitted_renderer_.set_eyes(true, true);
  fitted_renderer_.Pose(fitted);
  target_renderer_.Pose(posed_target);
  EyeRegionView view;
  view.region = (ModelBounds(fitted_renderer_.posed(), camera, 0.02) |
                 ModelBounds(target_renderer_.posed(), camera, 0.02)) & cv::Rect(cv::Point(0, 0), image_size);
  if (view.region.width < 8 || view.region.height < 4) {
    note = "the eyes are outside the image";
    return std::nullopt;
  }
  view.camera = camera.Cropped(view.region.x, view.region.y, view.region.width, view.region.height);
  fitted_renderer_.Rasterize(view.camera, fitted_buffers_);
  fitted_renderer_.Shade(fitted, view.camera, fitted_buffers_);
  view.eyes = OpenEyes(fitted, view.camera, note);
  if (!view.eyes[0] && !view.eyes[1]) return std::nullopt;
  view.slit = SlitShares(fitted, view.camera);
  if (!view.eyes[0] || !view.eyes[1]) {  // only the open eye's parts from here on
    fitted_renderer_.set_eyes(view.eyes[0], view.eyes[1]);
    fitted_renderer_.Rasterize(view.camera, fitted_buffers_);
    fitted_renderer_.Shade(fitted, view.camera, fitted_buffers_);
  }
  target_renderer_.set_eyes(view.eyes[0], view.eyes[1]);
  target_renderer_.Render(posed_target, view.camera, target_buffers_);
  return view;
}

Highlights Redirector::FindHighlights(const cv::Mat& photo, const Camera& crop_camera, const Parameters& fitted,
                                      const Parameters& posed_target, const cv::Mat& fitted_cornea) {
  Highlights highlights;
  // Reflections: the environment that explains the photo's highlights.
  const auto& maps = BuiltInEnvironmentMaps();
  const bool valid = options_.environment >= 0 && options_.environment < static_cast<int>(maps.size());
  const int fixed = valid ? options_.environment : -1;
  double& gain = highlights.gain;
  highlights.environment =
      options_.specular ? ChooseEnvironment(photo, crop_camera, fixed, gain, highlights.old_specular) : fixed;
  if (gain > 0) {
    Reflections(target_renderer_, target_buffers_, crop_camera, maps[highlights.environment], highlights.new_specular);
  }
  if (!options_.move_glints || !options_.transfer_eyeballs) return highlights;
  // The photo's own glints, moved as the corneas move, stand in for the
  // environment's strong reflections (its faint ones stay).
  highlights.glints = FindGlints(photo, fitted_buffers_, fitted_cornea);
  const Glints& glints = highlights.glints;
  if (glints.found[0] || glints.found[1]) {
    highlights.moved_glints = MovedGlints(glints, GlintShifts(fitted, posed_target, crop_camera), target_buffers_);
  }
  if (gain > 0) KeepFaintReflections(highlights.new_specular, target_buffers_, static_cast<float>(kHighlight / gain));
  // A filled glint has lost its light already; taking the environment's
  // highlight there off it again would leave a dark rim beside the moved
  // glint (s42.jpg at the camera: a black dash under it).
  if (gain > 0 && !glints.filled.empty()) highlights.old_specular.setTo(cv::Scalar::all(0), glints.filled);
  return highlights;
}

}  // namespace gazedirector
