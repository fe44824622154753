#pragma once

#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "gazedirector/geometry/camera.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/model/parameters.h"
#include "gazedirector/render/rasterizer.h"

namespace gazedirector {

// Everything one render produces, per pixel of the target (the camera's
// image, usually a region of interest around the eyes).
struct RenderBuffers {
  VisibilityBuffer visibility;        // triangle id (into EyeRegionModel::all_triangles), depth, barycentrics
  std::vector<int> foreground;        // covered pixel indices, in raster order
  // RGB in [0, 1] of each foreground pixel: row i is pixel foreground[i]
  // (each channel contiguous, for vector loads).
  Eigen::Matrix<float, Eigen::Dynamic, 3> colour;
  std::array<int32_t, kNumParts + 1> part_offsets{};  // triangle ids of part p: [offsets[p], offsets[p + 1])

  int width() const { return visibility.width(); }
  int height() const { return visibility.height(); }
  // The part a covered pixel shows, or -1.
  int PartAt(int pixel) const {
    const int32_t id = visibility.triangle(pixel);
    if (id < 0) return -1;
    return (id >= part_offsets[1]) + (id >= part_offsets[2]) + (id >= part_offsets[3]);
  }
  // Pictures for people: 8-bit BGR colour over `background` (black when
  // empty), the foreground mask (255 inside) and part ids (255 for none).
  cv::Mat ColourImage(const cv::Mat& background = cv::Mat()) const;
  cv::Mat MaskImage() const;
  cv::Mat PartImage() const;
  cv::Mat EyeballMaskImage() const;  // 255 where an eyeball shows
};

// Shading constants of the eyeball: ambient occlusion under the lids.
struct EyeballShading {
  float upper_lid_occlusion = 0.55f;  // darkening at the upper lid margin
  float lower_lid_occlusion = 0.25f;
  float occlusion_width_rad = 0.10f;  // how far from the margin the shadow fades (about 6 degrees)
};

// The CPU renderer of the eye-region model: poses Φ, rasterizes the four
// parts into a visibility buffer with a depth test, then shades each covered
// pixel once (Lambertian ambient + directional light, the skin texture from
// the PCA with its look-down blend, the tinted, refracted eyeball with
// ambient occlusion from the lids). One Renderer per thread; buffers are
// reused, so steady-state rendering allocates nothing.
class Renderer {
 public:
  explicit Renderer(std::shared_ptr<const EyeRegionModel> model);

  // Poses, rasterizes and shades: the whole analysis-by-synthesis image.
  void Render(const Parameters& phi, const Camera& camera, RenderBuffers& out);

  // The steps of Render, for callers that change only some of them.
  void Pose(const Parameters& phi);
  void Rasterize(const Camera& camera, RenderBuffers& out);
  void Shade(const Parameters& phi, const Camera& camera, RenderBuffers& out);

  // Interpolates per-vertex attributes (channels x vertices, per part; an
  // empty matrix leaves that part's pixels at 0) over the pixels of `buffers`:
  // the dense fields of the redirection's flow, for example. Returns a float
  // image with `channels` channels.
  static cv::Mat InterpolateAttribute(const RenderBuffers& buffers, const EyeRegionModel& model,
                                      const std::array<Eigen::MatrixXf, kNumParts>& attributes, int channels);
  // The attribute that is 1 on the eyeballs' corneas (through which the
  // irises show) and 0 elsewhere, for InterpolateAttribute.
  static std::array<Eigen::MatrixXf, kNumParts> CorneaAttribute(const EyeRegionModel& model);

  // d(colour)/d(parameter) of every foreground pixel, exact, from the last
  // Render with `phi`, for the parameters that colour is linear in (texture
  // PCA, iris and sclera colours, ambient and directional light colour) and
  // the light's direction (colour is affine in the Lambertian factor, which
  // moves by n.dl/dθ at each vertex the light reaches; the geometry does not
  // move): row 3i + c is channel c of foreground pixel i, columns follow
  // ExactParameters().
  void ExactJacobian(const Parameters& phi, const Camera& camera, const RenderBuffers& buffers,
                     Eigen::MatrixXf& jacobian) const;
  // Only the columns `which` (indices into ExactParameters()), in that
  // order: a fit that holds the texture skips sampling its eight modes.
  void ExactJacobian(const Parameters& phi, const Camera& camera, const RenderBuffers& buffers,
                     const std::vector<int>& which, Eigen::MatrixXf& jacobian) const;
  static const std::vector<int>& ExactParameters();

  // Renders only the parts of these eyes (both by default): a single eye is
  // fitted to a crop of one eye.
  void set_eyes(bool left, bool right) { eyes_ = {left, right}; }

  // Off, every eyeball triangle is drawn, not only the patches that face the
  // camera and reach the eye opening (for tests: the buffers are the same).
  void set_eyeball_culling(bool on) { eyeball_culling_ = on; }

  const PosedModel& posed() const { return posed_; }
  const EyeRegionModel& model() const { return *model_; }
  EyeballShading& eyeball_shading() { return eyeball_shading_; }

 private:
  void DrawEyeball(int eye, const Camera& camera, const Eigen::Vector3i* triangles, int32_t first,
                   const Eigen::Vector4i& window, RenderBuffers& out) const;
  void ComposeSkinTexture(const Parameters& phi);
  struct ShadingInputs;
  void MixLookingDown(ShadingInputs& in);
  struct PixelShading;
  // Texture u, v and the Lambertian factor at barycentrics (b1, b2) of a triangle (all_triangles' index).
  [[gnu::always_inline]] inline Eigen::Vector4f SurfaceAt(int32_t triangle, float b1, float b2) const;
  [[gnu::always_inline]] inline PixelShading ShadePixel(const ShadingInputs& in, int index, const RenderBuffers& out) const;
  // The same from the pixel's surface values (SurfaceAt) where they are known already.
  [[gnu::always_inline]] inline PixelShading ShadeSurface(const ShadingInputs& in, int pixel, const Eigen::Vector4f& surface,
                                                          const RenderBuffers& out) const;
  ShadingInputs Inputs(const Parameters& phi, const Camera& camera) const;
  // Per vertex (all parts' columns), d(max(0, n.l))/d(light pitch, yaw) per degree at the last pose.
  Eigen::Matrix2Xf LambertDerivatives(const Parameters& phi) const;
  static constexpr int kShadingChunk = 64;  // pixels; a bit mask marks its eyeball pixels
  void ShadeChunk(const ShadingInputs& in, int first, RenderBuffers& out) const;

  std::shared_ptr<const EyeRegionModel> model_;
  PosedModel posed_;
  PoseWorkspace workspace_;
  std::vector<ScreenVertex> screen_;  // all parts' vertices, concatenated
  // Per vertex, packed for one vector load: texture u, v and the Lambertian
  // factor max(0, n.l) (the fourth float pads).
  Eigen::Matrix<float, 4, Eigen::Dynamic> surface_;
  // Per triangle, where its corners' columns of `surface_` start (in floats):
  // the shading's hottest loop then needs no index arithmetic.
  std::vector<std::array<int32_t, 3>> surface_offsets_;
  RgbaTexture skin_ahead_;  // the composed skin texture
  RgbaTexture skin_down_;
  Eigen::Matrix<double, kNumTextureModes, 1> composed_for_;
  bool composed_ = false;
  // One level of the composed skin looking down as far as `mixed_blend_`
  // says: a render then samples one texture instead of two.
  std::vector<float> skin_mixed_;
  int mixed_level_ = -1;
  float mixed_blend_ = 0;
  EyeballShading eyeball_shading_;
  std::array<bool, 2> eyes_ = {true, true};
  bool eyeball_culling_ = true;
};

}  // namespace gazedirector
