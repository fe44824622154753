#include "gazedirector/render/renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "gazedirector/model/eye_region_topology.h"
#include "gazedirector/util/simd.h"

namespace gazedirector {
namespace {

// Texels per millimetre of the textures at level 0, measured on the model:
// the skin map spans about 70 mm of face; the eyeball's limbus (5.87 mm) is
// 0.1385 of its uv width.
constexpr float kSkinTexelsPerMm = SkinTextureModel::kSize / 70.0f;
constexpr float kEyeballUvPerMm = topology::kLimbusUvRadius / topology::kLimbusRadiusMm;

float Cubic(const Eigen::Vector4f& c, float x) { return c[0] + x * (c[1] + x * (c[2] + x * c[3])); }

// Darkening that fades smoothly from `strength` at the lid margin to none at
// `width` away from it (cheaper than an exponential, with compact support).
float Occlusion(float distance, float strength, float width) {
  const float t = std::max(0.0f, 1.0f - distance / width);
  return 1.0f - strength * t * t;
}

// Whether a ball (camera frame, mm) may cover pixel centres of `window`
// (pixels, inclusive): its projection lies within the range of x / z and
// y / z over the ball's bounding box, widened by a pixel for snapping.
bool MayReach(const Camera& camera, const Eigen::Vector3d& centre, double radius, const Eigen::Vector4i& window) {
  const double nearest = centre.z() - radius, farthest = centre.z() + radius;
  if (nearest <= 1.0) return true;
  auto reaches = [&](double middle, double focal, double principal, int low, int high) {
    const double from = middle - radius, to = middle + radius;
    const double first = focal * from / (from < 0 ? nearest : farthest) + principal;
    const double last = focal * to / (to > 0 ? nearest : farthest) + principal;
    return last + 1 >= low && first - 1 <= high;
  };
  return reaches(centre.x(), camera.fx, camera.cx, window[0], window[2]) &&
         reaches(centre.y(), camera.fy, camera.cy, window[1], window[3]);
}

// Bit j set where ids[j] (j < count <= 64) is at least `first`.
uint64_t EyeballBits(const int32_t* ids, int count, int32_t first) {
  uint64_t bits = 0;
  int j = 0;
#if defined(__AVX2__)
  const __m256i below = _mm256_set1_epi32(first - 1);
  for (; j + 8 <= count; j += 8) {
    const __m256i chunk = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ids + j));
    const unsigned byte = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(chunk, below))));
    bits |= static_cast<uint64_t>(byte) << j;
  }
#endif
  for (; j < count; ++j) bits |= static_cast<uint64_t>(ids[j] >= first) << j;
  return bits;
}

// The first three floats of `count` packed groups of four, as three arrays
// (eight groups at a time with AVX2: a store of four floats per pixel and a
// transpose cost less than three scalar stores per pixel).
void SplitThree(const float* packed, int count, float* first, float* second, float* third) {
  int i = 0;
#if defined(__AVX2__)
  for (; i + 8 <= count; i += 8) {
    const float* p = packed + 4 * i;
    auto row = [&](int k) { return _mm256_loadu2_m128(p + 4 * (k + 4), p + 4 * k); };  // groups k | k + 4
    const simd::Channels group = simd::Transpose(row(0), row(1), row(2), row(3));
    _mm256_storeu_ps(first + i, group.x);
    _mm256_storeu_ps(second + i, group.y);
    _mm256_storeu_ps(third + i, group.z);
  }
#endif
  for (; i < count; ++i) first[i] = packed[4 * i], second[i] = packed[4 * i + 1], third[i] = packed[4 * i + 2];
}

}  // namespace

cv::Mat RenderBuffers::ColourImage(const cv::Mat& background) const {
  cv::Mat image = background.empty() ? cv::Mat(height(), width(), CV_8UC3, cv::Scalar::all(0)) : background.clone();
  for (std::size_t i = 0; i < foreground.size(); ++i) {
    const Eigen::Index row = static_cast<Eigen::Index>(i);
    image.at<cv::Vec3b>(foreground[i] / width(), foreground[i] % width()) =
        cv::Vec3b(cv::saturate_cast<uchar>(255 * colour(row, 2)), cv::saturate_cast<uchar>(255 * colour(row, 1)),
                  cv::saturate_cast<uchar>(255 * colour(row, 0)));
  }
  return image;
}

cv::Mat RenderBuffers::MaskImage() const {
  cv::Mat mask(height(), width(), CV_8UC1, cv::Scalar(0));
  for (int pixel : foreground) mask.data[pixel] = 255;
  return mask;
}

cv::Mat RenderBuffers::EyeballMaskImage() const {
  cv::Mat mask(height(), width(), CV_8UC1, cv::Scalar(0));
  for (int pixel : foreground) {
    if (IsEyeball(PartAt(pixel))) mask.data[pixel] = 255;
  }
  return mask;
}

cv::Mat RenderBuffers::PartImage() const {
  cv::Mat parts(height(), width(), CV_8UC1, cv::Scalar(255));
  for (int pixel : foreground) parts.data[pixel] = static_cast<uchar>(PartAt(pixel));
  return parts;
}

Renderer::Renderer(std::shared_ptr<const EyeRegionModel> model) : model_(std::move(model)) {
  screen_.resize(static_cast<std::size_t>(model_->total_vertices()));
  surface_.setZero(4, model_->total_vertices());
  surface_offsets_.reserve(model_->all_triangles().size());
  for (const Eigen::Vector3i& t : model_->all_triangles()) surface_offsets_.push_back({4 * t[0], 4 * t[1], 4 * t[2]});
}

void Renderer::Render(const Parameters& phi, const Camera& camera, RenderBuffers& out) {
  Pose(phi);
  Rasterize(camera, out);
  Shade(phi, camera, out);
}

void Renderer::Pose(const Parameters& phi) { model_->Pose(phi, posed_, workspace_); }

void Renderer::Rasterize(const Camera& camera, RenderBuffers& out) {
  out.visibility.Reset(camera.width, camera.height);
  const float fx = static_cast<float>(camera.fx), fy = static_cast<float>(camera.fy);
  const float cx = static_cast<float>(camera.cx), cy = static_cast<float>(camera.cy);
  for (int part = 0; part < kNumParts; ++part) {
    if (!eyes_[EyeOfPart(part)]) continue;
    const Eigen::Matrix3Xf& positions = posed_.parts[part].positions;
    ScreenVertex* screen = screen_.data() + model_->vertex_offset(part);
    ProjectVertices(positions.data(), static_cast<int>(positions.cols()), fx, fy, cx, cy, screen);
  }
  const Eigen::Vector3i* triangles = model_->all_triangles().data();
  // Skin first: it hides most of the eyeballs, whose pixels then fail the depth test early.
  for (int part = 0; part < kNumParts; ++part) {
    const int first = model_->triangle_offset(part);
    const int count = model_->triangle_offset(part + 1) - first;
    out.part_offsets[part] = first;
    if (!eyes_[EyeOfPart(part)]) continue;
    if (!IsEyeball(part)) {
      out.visibility.Draw(screen_.data(), triangles + first, count, first);
      continue;
    }
    // The eyeball shows only through the eye opening: rasterize it within the
    // opening's outline on screen.
    const ScreenVertex* skin = screen_.data() + model_->vertex_offset(SkinPart(EyeOfPart(part)));
    Eigen::Vector4i window(std::numeric_limits<int>::max(), std::numeric_limits<int>::max(),
                           std::numeric_limits<int>::min(), std::numeric_limits<int>::min());
    for (int v : model_->opening_rim()) {
      window = Eigen::Vector4i(std::min(window[0], skin[v].x), std::min(window[1], skin[v].y),
                               std::max(window[2], skin[v].x), std::max(window[3], skin[v].y));
    }
    window = Eigen::Vector4i((window[0] >> kSubpixelBits) - 1, (window[1] >> kSubpixelBits) - 1,
                             (window[2] >> kSubpixelBits) + 2, (window[3] >> kSubpixelBits) + 2);
    DrawEyeball(EyeOfPart(part), camera, triangles + first, first, window, out);
  }
  out.part_offsets[kNumParts] = model_->triangle_offset(kNumParts);
  out.visibility.CollectCovered(out.foreground);
}

// Draws the eyeball's patches that face the camera and may reach the window,
// consecutive patches in one call: most of the eyeball's triangles face away
// or lie behind the skin around the opening, and are never set up.
void Renderer::DrawEyeball(int eye, const Camera& camera, const Eigen::Vector3i* triangles, int32_t first,
                           const Eigen::Vector4i& window, RenderBuffers& out) const {
  const PosedEye& posed = posed_.eyes[eye];
  const Eigen::Vector3d camera_in_eyeball = posed.CameraInEyeball();
  int run_begin = 0, run_end = 0;
  auto draw_run = [&] {
    if (run_end > run_begin) {
      out.visibility.Draw(screen_.data(), triangles + run_begin, run_end - run_begin, first + run_begin, window);
    }
  };
  for (const EyeballPatch& patch : model_->eyeball().patches()) {
    if (eyeball_culling_ && (patch.FacesAwayFrom(camera_in_eyeball) ||
                             !MayReach(camera, posed.eyeball_to_camera * patch.centre + posed.centre, patch.radius, window))) {
      continue;
    }
    if (patch.begin != run_end) {
      draw_run();
      run_begin = patch.begin;
    }
    run_end = patch.end;
  }
  draw_run();
}

void Renderer::ComposeSkinTexture(const Parameters& phi) {
  const Eigen::Matrix<double, kNumTextureModes, 1> tau = phi.texture();
  if (composed_ && tau == composed_for_) return;
  model_->skin_texture().Compose(tau.data(), skin_ahead_, skin_down_);
  composed_for_ = tau;
  composed_ = true;
  mixed_level_ = -1;
  // Room for the largest level, so that rendering allocates nothing later.
  skin_mixed_.resize(static_cast<std::size_t>(skin_ahead_.size()) * skin_ahead_.size() * 4);
}

// What shading one render needs, gathered once.
struct Renderer::ShadingInputs {
  RgbaTexture::Level skin_ahead;
  RgbaTexture::Level skin_down;
  RgbaTexture::Level skin;  // the two already mixed by `blend`, when `mixed`
  bool mixed;
  RgbaTexture::Level eyeball;
  int skin_level;
  float blend;
  Eigen::Vector3f iris, sclera;
  Eigen::Vector3f ambient, light_colour;
  Eigen::Vector4f upper_lid[2], lower_lid[2];
  EyeballShading shading;
  // The pupil's radius in the texture's uv and as fitted (equal: no
  // resizing), and how much the texture is read stretched inside and
  // outside it (SetPupil).
  float texture_pupil_uv, pupil_uv, inside_pupil, outside_pupil;

  void SetPupil(double pupil_size) {
    constexpr float kLimbus = static_cast<float>(topology::kLimbusUvRadius);
    texture_pupil_uv = static_cast<float>(topology::kLimbusUvRadius * topology::kTexturePupilSize);
    pupil_uv = static_cast<float>(topology::kLimbusUvRadius * pupil_size);
    inside_pupil = texture_pupil_uv / pupil_uv;
    outside_pupil = (kLimbus - texture_pupil_uv) / (kLimbus - pupil_uv);
  }

  // Where the eyeball texture is read for uv (u, v): with the pupil resized,
  // the iris between it and the limbus stretches or shrinks radially.
  Eigen::Vector2f EyeballUv(float u, float v) const {
    constexpr float kLimbus = static_cast<float>(topology::kLimbusUvRadius);
    if (pupil_uv == texture_pupil_uv) return {u, v};
    const float du = u - 0.5f, dv = v - 0.5f;
    const float radius = std::sqrt(du * du + dv * dv);
    if (radius >= kLimbus || radius <= 0) return {u, v};
    const float read =
        radius < pupil_uv ? radius * inside_pupil : texture_pupil_uv + (radius - pupil_uv) * outside_pupil;
    const float scale = read / radius;
    return {0.5f + du * scale, 0.5f + dv * scale};
  }

  // Ambient plus directional light at a Lambertian factor (ShadeChunk applies
  // the same per channel, vectorised).
  Eigen::Vector3f Light(float lambert) const { return ambient + light_colour * lambert; }

  // The skin's colour before lighting at a located texel (both skin
  // textures share their size), looking down as far as `blend` says.
  Eigen::Vector4f SkinAlbedo(int32_t offset, float fx, float fy) const {
    if (mixed) return skin.SampleAt(offset, fx, fy);
    Eigen::Vector4f albedo = skin_ahead.SampleAt(offset, fx, fy);
    if (blend > 0) albedo += blend * (skin_down.SampleAt(offset, fx, fy) - albedo);
    return albedo;
  }
};

// One pixel's shading and the pieces its linear derivatives need.
struct Renderer::PixelShading {
  Eigen::Vector2f uv;      // interpolated texture coordinates
  float lambert;           // interpolated Lambertian factor max(0, n.l)
  Eigen::Vector3f light;   // ambient + directional light
  Eigen::Vector3f albedo;  // colour before lighting
  bool eyeball;
  Eigen::Vector3f base;    // eyeball: texture colour with occlusion, before tinting
  float iris_weight;       // eyeball: 1 on the iris, 0 on the sclera
};

Renderer::ShadingInputs Renderer::Inputs(const Parameters& phi, const Camera& camera) const {
  ShadingInputs in;
  // Mip levels that keep texels about a pixel in size.
  const float pixels_per_mm = static_cast<float>(camera.fx / std::max(posed_.eyes[eyes_[0] ? 0 : 1].centre.z(), 1.0));
  in.skin_level = skin_ahead_.LevelFor(kSkinTexelsPerMm / pixels_per_mm);
  in.skin_ahead = skin_ahead_.level(in.skin_level);
  in.skin_down = skin_down_.level(in.skin_level);
  const RgbaTexture& eyeball = model_->eyeball_texture();
  in.eyeball = eyeball.level(eyeball.LevelFor(eyeball.size() * kEyeballUvPerMm / pixels_per_mm));
  in.blend = posed_.look_down_blend;
  in.mixed = in.blend <= 0 || (mixed_level_ == in.skin_level && mixed_blend_ == in.blend);
  in.skin = in.blend <= 0 ? in.skin_ahead : RgbaTexture::Level{skin_mixed_.data(), in.skin_ahead.size};
  in.iris = phi.iris_colour().cast<float>();
  in.sclera = phi.sclera_tint().cast<float>();
  in.ambient = phi.ambient().cast<float>();
  in.light_colour = phi.light_colour().cast<float>();
  for (int eye = 0; eye < 2; ++eye) {
    in.upper_lid[eye] = posed_.eyes[eye].upper_lid.cast<float>();
    in.lower_lid[eye] = posed_.eyes[eye].lower_lid.cast<float>();
  }
  in.shading = eyeball_shading_;
  in.SetPupil(phi.pupil_size());
  return in;
}

// Mixes the look-down skin into `in.skin` for a blend and level it was not
// mixed for yet (Inputs already points `in.skin` at the mix).
void Renderer::MixLookingDown(ShadingInputs& in) {
  if (in.mixed) return;
  const std::size_t floats = static_cast<std::size_t>(in.skin_ahead.size) * in.skin_ahead.size * 4;
  const float* ahead = in.skin_ahead.texels;
  const float* down = in.skin_down.texels;
  for (std::size_t i = 0; i < floats; ++i) skin_mixed_[i] = ahead[i] + in.blend * (down[i] - ahead[i]);
  mixed_level_ = in.skin_level;
  mixed_blend_ = in.blend;
  in.mixed = true;
}

inline Eigen::Vector4f Renderer::SurfaceAt(int32_t triangle, float b1, float b2) const {
  // The weights are broadcast before b0 is formed, lane by lane (fewer shuffles than in scalars).
  const Eigen::Vector4f w1 = Eigen::Vector4f::Constant(b1), w2 = Eigen::Vector4f::Constant(b2);
  const Eigen::Vector4f w0 = Eigen::Vector4f::Ones() - w1 - w2;
  using Values = Eigen::Map<const Eigen::Vector4f, Eigen::Aligned16>;
  const float* values = surface_.data();
  const std::array<int32_t, 3>& corners = surface_offsets_[triangle];
  return w0.cwiseProduct(Values(values + corners[0])) + w1.cwiseProduct(Values(values + corners[1])) +
         w2.cwiseProduct(Values(values + corners[2]));
}

inline Renderer::PixelShading Renderer::ShadePixel(const ShadingInputs& in, int index, const RenderBuffers& out) const {
  const VisibilityBuffer& vis = out.visibility;
  const int pixel = out.foreground[index];
  return ShadeSurface(in, pixel, SurfaceAt(vis.triangle(pixel), vis.b1(pixel), vis.b2(pixel)), out);
}

inline Renderer::PixelShading Renderer::ShadeSurface(const ShadingInputs& in, int pixel, const Eigen::Vector4f& a,
                                                     const RenderBuffers& out) const {
  const VisibilityBuffer& vis = out.visibility;
  const int part = out.PartAt(pixel);
  PixelShading shading;
  shading.uv = a.head<2>();
  shading.lambert = a[2];
  shading.light = in.Light(shading.lambert);
  shading.eyeball = IsEyeball(part);
  if (!shading.eyeball) {
    int32_t offset;
    float fx, fy;
    in.skin_ahead.Locate(a[0], a[1], offset, fx, fy);
    shading.albedo = in.SkinAlbedo(offset, fx, fy).head<3>();
  } else {
    const Eigen::Vector2f uv = in.EyeballUv(a[0], a[1]);
    const Eigen::Vector4f base = in.eyeball.Sample(uv[0], uv[1]);
    // Ambient occlusion: darker toward the lid margins, in the eyeball's
    // angular frame (azimuth, elevation).
    const int eye = EyeOfPart(part);
    const Eigen::Matrix2Xf& angles = model_->eyeball_angles();
    const Eigen::Vector3i& corners = model_->triangles(part)[vis.triangle(pixel) - model_->triangle_offset(part)];
    const Eigen::Vector2f angle = vis.Interpolate(pixel, angles, corners);
    const float below_upper = std::max(0.0f, Cubic(in.upper_lid[eye], angle[0]) - angle[1]);
    const float above_lower = std::max(0.0f, angle[1] - Cubic(in.lower_lid[eye], angle[0]));
    const float occlusion = Occlusion(below_upper, in.shading.upper_lid_occlusion, in.shading.occlusion_width_rad) *
                            Occlusion(above_lower, in.shading.lower_lid_occlusion, in.shading.occlusion_width_rad);
    shading.base = base.head<3>() * occlusion;
    shading.iris_weight = base[3];
    shading.albedo = shading.base.cwiseProduct(shading.iris_weight * in.iris + (1 - shading.iris_weight) * in.sclera);
  }
  return shading;
}

void Renderer::Shade(const Parameters& phi, const Camera& camera, RenderBuffers& out) {
  ComposeSkinTexture(phi);
  // Per vertex: texture coordinates and the Lambertian factor. The light's
  // colours are applied per pixel (colour is affine in the factor).
  const Eigen::Vector3f light = phi.LightDirection().cast<float>();
  for (int part = 0; part < kNumParts; ++part) {
    if (!eyes_[EyeOfPart(part)]) continue;
    const PosedPart& posed = posed_.parts[part];
    const int offset = model_->vertex_offset(part);
    for (Eigen::Index i = 0; i < posed.normals.cols(); ++i) {
      auto a = surface_.col(offset + i);
      a.head<2>() = posed.uvs.col(i);
      a[2] = std::max(0.0f, posed.normals.col(i).dot(light));
    }
  }
  ShadingInputs in = Inputs(phi, camera);
  MixLookingDown(in);
  out.colour.resize(static_cast<Eigen::Index>(out.foreground.size()), 3);
  for (int first = 0; first < static_cast<int>(out.foreground.size()); first += kShadingChunk) {
    ShadeChunk(in, first, out);
  }
}

// The skin covers most pixels, so its path is split into branch-free passes
// over a chunk of pixels: interpolate, find the texels (a vectorised loop),
// sample, light (vectorised). Every pixel takes them, eyeball pixels too
// (their texture coordinates are in range), which is cheaper than telling
// them apart; eyeball pixels are then shaded again by ShadeSurface.
void Renderer::ShadeChunk(const ShadingInputs& in, int first, RenderBuffers& out) const {
  const int count = std::min(kShadingChunk, static_cast<int>(out.foreground.size()) - first);
  const VisibilityBuffer& vis = out.visibility;
  const int32_t first_eyeball = out.part_offsets[kLeftEyeball];
  alignas(64) std::array<float, kShadingChunk> u, v, fx, fy, lambert, albedo_r, albedo_g, albedo_b;
  alignas(64) std::array<int32_t, kShadingChunk> offset, ids;
  alignas(64) std::array<Eigen::Vector4f, kShadingChunk> packed;  // u, v, lambert; then the albedo
  for (int j = 0; j < count; ++j) {
    const int pixel = out.foreground[first + j];
    const int32_t id = ids[j] = vis.triangle(pixel);
    packed[j] = SurfaceAt(id, vis.b1(pixel), vis.b2(pixel));
  }
  SplitThree(packed[0].data(), count, u.data(), v.data(), lambert.data());
  in.skin_ahead.LocateMany(u.data(), v.data(), count, offset.data(), fx.data(), fy.data());
  for (int j = 0; j < count; ++j) packed[j] = in.skin.SampleAt(offset[j], fx[j], fy[j]);  // Shade mixed it
  SplitThree(packed[0].data(), count, albedo_r.data(), albedo_g.data(), albedo_b.data());
  const Eigen::Index rows = out.colour.rows();
  float* red = out.colour.data() + first;
  float* green = red + rows;
  float* blue = green + rows;
  const float ambient_r = in.ambient[0], ambient_g = in.ambient[1], ambient_b = in.ambient[2];
  const float light_r = in.light_colour[0], light_g = in.light_colour[1], light_b = in.light_colour[2];
  for (int j = 0; j < count; ++j) {
    red[j] = albedo_r[j] * (ambient_r + light_r * lambert[j]);
    green[j] = albedo_g[j] * (ambient_g + light_g * lambert[j]);
    blue[j] = albedo_b[j] * (ambient_b + light_b * lambert[j]);
  }
  for (uint64_t eyeballs = EyeballBits(ids.data(), count, first_eyeball); eyeballs != 0; eyeballs &= eyeballs - 1) {
    const int j = __builtin_ctzll(eyeballs);
    // The chunk's interpolation above already gave this pixel's surface values.
    const Eigen::Vector4f surface(u[j], v[j], lambert[j], 0.0f);
    const PixelShading shading = ShadeSurface(in, out.foreground[first + j], surface, out);
    out.colour.row(first + j) = shading.albedo.cwiseProduct(shading.light).transpose();
  }
}

const std::vector<int>& Renderer::ExactParameters() {
  static const std::vector<int> parameters = [] {
    std::vector<int> indices;
    for (Block block : {Block::kTexture, Block::kIrisColour, Block::kScleraTint, Block::kAmbient, Block::kLightColour,
                        Block::kLightDirection}) {
      for (int i = 0; i < LayoutOf(block).size; ++i) indices.push_back(LayoutOf(block).offset + i);
    }
    return indices;
  }();
  return parameters;
}

void Renderer::ExactJacobian(const Parameters& phi, const Camera& camera, const RenderBuffers& buffers,
                             Eigen::MatrixXf& jacobian) const {
  std::vector<int> all(ExactParameters().size());
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  ExactJacobian(phi, camera, buffers, all, jacobian);
}

Eigen::Matrix2Xf Renderer::LambertDerivatives(const Parameters& phi) const {
  // d(max(0, n.l))/dθ = n.dl/dθ where n.l > 0, per degree of the light's pitch and yaw.
  const Eigen::Vector3f light = phi.LightDirection().cast<float>();
  const Eigen::Matrix<float, 3, 2> by_angle = phi.LightDirectionJacobian().cast<float>();
  const Eigen::Vector3f by_pitch = by_angle.col(0), by_yaw = by_angle.col(1);
  Eigen::Matrix2Xf derivatives = Eigen::Matrix2Xf::Zero(2, surface_.cols());
  for (int part = 0; part < kNumParts; ++part) {
    if (!eyes_[EyeOfPart(part)]) continue;
    const Eigen::Matrix3Xf& normals = posed_.parts[part].normals;
    const int offset = model_->vertex_offset(part);
    for (Eigen::Index i = 0; i < normals.cols(); ++i) {
      if (normals.col(i).dot(light) <= 0.0f) continue;
      derivatives.col(offset + i) = Eigen::Vector2f(normals.col(i).dot(by_pitch), normals.col(i).dot(by_yaw));
    }
  }
  return derivatives;
}

void Renderer::ExactJacobian(const Parameters& phi, const Camera& camera, const RenderBuffers& buffers,
                             const std::vector<int>& which, Eigen::MatrixXf& jacobian) const {
  constexpr int kTexture = 0, kIris = kNumTextureModes, kSclera = kIris + 3, kAmbient = kSclera + 3;
  constexpr int kLight = kAmbient + 3, kDirection = kLight + 3;
  const int count = static_cast<int>(buffers.foreground.size());
  jacobian.setZero(3 * count, static_cast<Eigen::Index>(which.size()));
  // Each requested parameter's column, or -1.
  std::array<int, kDirection + 2> column;
  column.fill(-1);
  for (std::size_t k = 0; k < which.size(); ++k) column[which[k]] = static_cast<int>(k);
  bool any_texture = false;
  for (int j = 0; j < kNumTextureModes; ++j) any_texture = any_texture || column[kTexture + j] >= 0;
  const ShadingInputs in = Inputs(phi, camera);
  std::array<RgbaTexture::Level, 2 * kNumTextureModes> modes;
  for (int j = 0; j < kNumTextureModes; ++j) {
    modes[2 * j] = model_->texture_mode(j, 0).level(in.skin_level);
    modes[2 * j + 1] = model_->texture_mode(j, 1).level(in.skin_level);
  }
  // Each colour parameter moves one channel; entries not set stay zero.
  auto set = [&](int i, int c, int parameter, float value) {
    if (column[parameter] >= 0) jacobian(3 * i + c, column[parameter]) = value;
  };
  const bool any_direction = column[kDirection] >= 0 || column[kDirection + 1] >= 0;
  const Eigen::Matrix2Xf lambert_derivatives = any_direction ? LambertDerivatives(phi) : Eigen::Matrix2Xf();
  const VisibilityBuffer& vis = buffers.visibility;
  for (int i = 0; i < count; ++i) {
    const PixelShading s = ShadePixel(in, i, buffers);
    const Eigen::Vector3f& shade = s.light;
    for (int c = 0; c < 3; ++c) {
      set(i, c, kAmbient + c, s.albedo[c]);
      set(i, c, kLight + c, s.albedo[c] * s.lambert);
    }
    if (any_direction) {
      // The Lambertian factor is interpolated from the vertices' as in SurfaceAt.
      const int pixel = buffers.foreground[i];
      const Eigen::Vector2f lambert =
          vis.Interpolate(pixel, lambert_derivatives, model_->all_triangles()[vis.triangle(pixel)]);
      for (int c = 0; c < 3; ++c) {
        const float per_lambert = s.albedo[c] * in.light_colour[c];
        set(i, c, kDirection, per_lambert * lambert[0]);
        set(i, c, kDirection + 1, per_lambert * lambert[1]);
      }
    }
    if (s.eyeball) {
      for (int c = 0; c < 3; ++c) {
        set(i, c, kIris + c, s.base[c] * s.iris_weight * shade[c]);
        set(i, c, kSclera + c, s.base[c] * (1 - s.iris_weight) * shade[c]);
      }
      continue;
    }
    if (!any_texture) continue;
    // Every mode has the skin's size: the texels are found once.
    int32_t offset;
    float fx, fy;
    in.skin_ahead.Locate(s.uv.x(), s.uv.y(), offset, fx, fy);
    for (int j = 0; j < kNumTextureModes; ++j) {
      if (column[kTexture + j] < 0) continue;
      Eigen::Vector3f mode = modes[2 * j].SampleAt(offset, fx, fy).head<3>();
      if (in.blend > 0) mode += in.blend * (modes[2 * j + 1].SampleAt(offset, fx, fy).head<3>() - mode);
      for (int c = 0; c < 3; ++c) jacobian(3 * i + c, column[kTexture + j]) = mode[c] * shade[c];
    }
  }
}

cv::Mat Renderer::InterpolateAttribute(const RenderBuffers& buffers, const EyeRegionModel& model,
                                       const std::array<Eigen::MatrixXf, kNumParts>& attributes, int channels) {
  cv::Mat field(buffers.height(), buffers.width(), CV_32FC(channels), cv::Scalar::all(0));
  float* data = field.ptr<float>();
  const VisibilityBuffer& vis = buffers.visibility;
  for (int pixel : buffers.foreground) {
    const int part = buffers.PartAt(pixel);
    const Eigen::MatrixXf& values = attributes[part];
    if (values.size() == 0) continue;
    const Eigen::Vector3i& corners = model.triangles(part)[vis.triangle(pixel) - model.triangle_offset(part)];
    Eigen::Map<Eigen::VectorXf>(data + static_cast<std::size_t>(pixel) * channels, channels) =
        vis.Interpolate(pixel, values, corners);
  }
  return field;
}

std::array<Eigen::MatrixXf, kNumParts> Renderer::CorneaAttribute(const EyeRegionModel& model) {
  std::array<Eigen::MatrixXf, kNumParts> flags;
  const std::vector<bool>& is_cornea = model.eyeball().is_cornea();
  for (int part : {kLeftEyeball, kRightEyeball}) {
    flags[part].resize(1, static_cast<Eigen::Index>(is_cornea.size()));
    for (std::size_t v = 0; v < is_cornea.size(); ++v) flags[part](0, static_cast<Eigen::Index>(v)) = is_cornea[v];
  }
  return flags;
}

}  // namespace gazedirector
