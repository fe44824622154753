#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "gazedirector/geometry/camera.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/redirect/composite_recipe.h"
#include "gazedirector/redirect/environment_map.h"
#include "gazedirector/render/renderer.h"

namespace gazedirector {

struct Highlights;

struct RedirectOptions {
  // Warp the eyelids to follow the new gaze (off: "eyeballs only", one of
  // the evaluation's conditions).
  bool warp_eyelids = true;
  // Reuse the photo's own iris and sclera wherever the fitted eyeball showed
  // them (moved with the eyeball), the rendered eyeball elsewhere. Off: the
  // rendered eyeball everywhere, as in the paper.
  bool transfer_eyeballs = true;
  bool specular = true;             // add reflections of the chosen environment map
  // Move the photo's own corneal glints as the re-posed corneas would move
  // them (with the cornea's centre of curvature, about 0.58 of the iris's
  // motion), and keep the environment map's reflections faint (off: its
  // strong reflections stand in for the glints, as before session 60).
  // Only with transfer_eyeballs.
  bool move_glints = true;
  int environment = -1;             // the environment map; -1 picks the one that explains the photo best
  // Sclera the photo showed within this fraction of the interocular distance
  // of its lids carries the lashes' shade: it is reused only as near to the
  // new lids (the iris, dark itself, is reused anywhere).
  double margin_band = 0.02;
  double seam_blur = 0.012;         // Gaussian sigma of the eyeball seam, as a fraction of the interocular distance in pixels
  // Rendered sclera takes the colour of the photo's sclera within about this
  // fraction of the interocular distance (a Gaussian sigma); where none is
  // reused that near, the colour of the brighter half of the sclera the fit
  // showed deeper than the margin band (lids, lashes and the iris's edge,
  // which a small eye's sclera hardly escapes, are darker).
  double sclera_colour_reach = 0.03;
  // The photo's share of the new eyeballs fades into the rendering over this
  // fraction of the interocular distance (a Gaussian sigma, at least 0.8 px).
  double transfer_feather = 0.02;
  // An eye counts as closed (and is left alone) when less of its eyeball shows
  // than this fraction of its eye opening when open.
  double min_open_fraction = 0.15;
  double max_closure_deg = 22;      // or its lid closure exceeds this
  // An eye that shows less than slit_fraction of what it would show looking
  // level with its lids at rest (looking down under lowered lids: 0.3-0.6
  // on d3.mp4, open eyes mostly 0.7 and more) shows its iris and sclera only
  // as a slit of lashes: deeper than the margin band inside the new lids it
  // gets the rendered eyeball, not the slit's dark smear. Up to
  // clear_fraction the photo's share there fades in, so that a video's
  // frames do not flip between the two; the slit colours the rendering only
  // above halfway. slit_fraction >= clear_fraction: the photo's eye is
  // reused however little shows.
  double slit_fraction = 0.55;
  double clear_fraction = 0.7;
  // A face whose eyes are farther apart than this many pixels is redirected
  // at this size, and what was decided there is followed over the photo's
  // own pixels (CompositeRecipe): the masks, bands and thresholds above were
  // tuned on faces of 50-150 pixels, and at several times that they drew
  // hard edges and streaks.
  double working_interocular_px = 150;
};

// What one redirection did.
struct RedirectReport {
  std::array<bool, 2> redirected = {false, false};  // per eye (Eye index)
  std::string note;                                 // why an eye was left alone
  int environment = -1;                             // the environment map used
  double specular_gain = 0;
  cv::Rect region;                                  // the image region changed
};

// Pictures of the steps, for --debug-dir. All of the region's size (at the
// working size for faces larger than it).
struct RedirectLayers {
  cv::Mat flow;           // CV_32FC2: where each output pixel's skin comes from, minus its position
  cv::Mat skin_mask;      // 8-bit: the warped facial skin
  cv::Mat eyeball_mask;   // 8-bit: the new eyeballs
  cv::Mat transfer_mask;  // 8-bit: eyeball pixels taken from the photo (the rest rendered)
  cv::Mat sclera_mask;    // 8-bit: the new eyeballs' sclera (their corneas, which show the irises, excluded)
  cv::Mat eyeball_layer;  // 8-bit BGR: the composited eyeball colours
  cv::Mat specular;       // 8-bit: the added reflections
};

// The paper's gaze redirection: re-pose the fitted model, warp the eyelids of
// the photo with a dense flow field rasterized from the model, and composite
// new eyeballs between them. Not thread-safe; one per thread.
class Redirector {
 public:
  explicit Redirector(std::shared_ptr<const EyeRegionModel> model, RedirectOptions options = {});

  // Changes `image` (8-bit BGR) in place where the eyes of the face fitted
  // by `fitted` are, so that they look as in `target` (Φ re-posed: gaze and
  // eyelids). Eyes that are closed are left untouched and reported. A face
  // larger than options().working_interocular_px is redirected at that size
  // and the result followed over the image's own pixels.
  RedirectReport Redirect(cv::Mat& image, const Camera& camera, const Parameters& fitted, const Parameters& target,
                          RedirectLayers* layers = nullptr);

  RedirectOptions& options() { return options_; }

 private:
  // Redirect at the image's own size; `recipe` (when given) gets how each
  // pixel of the changed region was made.
  RedirectReport RedirectAtThisSize(cv::Mat& image, const Camera& camera, const Parameters& fitted,
                                    const Parameters& target, RedirectLayers* layers, CompositeRecipe* recipe);
  // Redirect a face larger than the working size (`scale` times it): the
  // eye region, shrunk to the working size, is redirected there and its
  // recipe followed at full size. The layers are of the working size.
  RedirectReport RedirectShrunk(cv::Mat& image, const Camera& camera, const Parameters& fitted,
                                const Parameters& target, double scale, RedirectLayers* layers);
  // The environment map and its gain that explain the photo's highlights on
  // the fitted eyes (rasterized in fitted_buffers_, `fitted_cornea` their
  // cornea attribute), and the photo's own glints moved onto the re-posed
  // eyes (in target_buffers_).
  Highlights FindHighlights(const cv::Mat& photo, const Camera& crop_camera, const Parameters& fitted,
                            const Parameters& posed_target, const cv::Mat& fitted_cornea);
  // The eye region of an image that the fit and the re-posed model cover,
  // as a camera of its own sees it, and which eyes are redirected there.
  struct EyeRegionView {
    cv::Rect region;
    Camera camera;                 // the image's, cropped to the region
    std::array<bool, 2> eyes;      // open enough to redirect (indexed by Eye)
    std::array<float, 2> slit;     // how much each is a slit of lashes (SlitShares)
  };
  // The view of `fitted` and `posed_target` in an image of `image_size`
  // seen by `camera`, both rendered there (fitted_buffers_ only with the
  // open eyes, target_buffers_): none where the eyes are closed or outside
  // the image (`note` says why; it names closed eyes among open ones too).
  std::optional<EyeRegionView> RenderBoth(const cv::Size& image_size, const Camera& camera, const Parameters& fitted,
                                          const Parameters& posed_target, std::string& note);
  // `target` as the redirection poses it: with the fitted lids when they are not warped.
  Parameters PosedTarget(const Parameters& fitted, const Parameters& target) const;
  // How many pixels of each eyeball `phi` shows in `crop` (rasterized with
  // target_renderer_ into target_buffers_).
  std::array<int, 2> EyeballPixels(const Parameters& phi, const Camera& crop);
  // The eyes of `fitted` (rendered in fitted_buffers_ over `crop`) open
  // enough to redirect; the others are named in `note`.
  std::array<bool, 2> OpenEyes(const Parameters& fitted, const Camera& crop, std::string& note);
  // How much each eye of the fit (in fitted_buffers_) is a slit of lashes,
  // by the fraction of its eyeball that shows against the same eye looking
  // level with its lids at rest: 0 from clear_fraction up, 1 below
  // slit_fraction, linear between.
  std::array<float, 2> SlitShares(const Parameters& fitted, const Camera& crop);
  // The environment map (`fixed`, or the best of all when -1) and its gain
  // whose reflections on the fitted eyeballs best explain the bright
  // residuals of the photo; `specular` gets those reflections (when gain > 0),
  // each no brighter than the photo's residual there.
  int ChooseEnvironment(const cv::Mat& photo, const Camera& camera, int fixed, double& gain, cv::Mat& specular);
  // Specular radiance (RGB, before the gain) of every eyeball pixel of
  // `buffers`, rendered by `renderer`; zero elsewhere.
  void Reflections(const Renderer& renderer, const RenderBuffers& buffers, const Camera& camera,
                   const EnvironmentMap& map, cv::Mat& specular) const;

  std::shared_ptr<const EyeRegionModel> model_;
  RedirectOptions options_;
  Renderer fitted_renderer_;
  Renderer target_renderer_;
  RenderBuffers fitted_buffers_;
  RenderBuffers target_buffers_;
  std::array<Eigen::MatrixXf, kNumParts> sources_;
  std::array<Eigen::MatrixXf, kNumParts> mirrors_;
  std::array<Eigen::MatrixXf, kNumParts> cornea_flags_;  // per eyeball vertex: 1 on the cornea (the iris shows), else 0
};

// Flow (CV_32FC2) as a picture: hue is direction, saturation is length
// (full at `scale` pixels).
cv::Mat FlowPicture(const cv::Mat& flow, double scale);

}  // namespace gazedirector
