#include "gazedirector/render/renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gazedirector/model/eye_region_topology.h"

namespace gazedirector {
namespace {

// Texels per millimetre of the textures at level 0, measured on the model:
// the skin map spans about 70 mm of face; the eyeball's limbus (5.87 mm) is
// 0.1385 of its uv width.
constexpr float kSkinTexelsPerMm = SkinTextureModel::kSize / 70.0f;
constexpr float kEyeballUvPerMm = topology::kLimbusUvRadius / topology::kLimbusRadiusMm;

using Attributes = Eigen::Matrix<float, 8, 1>;

float Cubic(const Eigen::Vector4f& c, float x) { return c[0] + x * (c[1] + x * (c[2] + x * c[3])); }

// Darkening that fades smoothly from `strength` at the lid margin to none at
// `width` away from it (cheaper than an exponential, with compact support).
float Occlusion(float distance, float strength, float width) {
  const float t = std::max(0.0f, 1.0f - distance / width);
  return 1.0f - strength * t * t;
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

cv::Mat RenderBuffers::PartImage() const {
  cv::Mat parts(height(), width(), CV_8UC1, cv::Scalar(255));
  for (int pixel : foreground) parts.data[pixel] = static_cast<uchar>(PartAt(pixel));
  return parts;
}

Renderer::Renderer(std::shared_ptr<const EyeRegionModel> model) : model_(std::move(model)) {
  screen_.resize(static_cast<std::size_t>(model_->total_vertices()));
  attributes_.setZero(8, model_->total_vertices());
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
    const Eigen::Matrix3Xf& positions = posed_.parts[part].positions;
    ScreenVertex* screen = screen_.data() + model_->vertex_offset(part);
    for (Eigen::Index i = 0; i < positions.cols(); ++i) {
      const float z = positions(2, i);
      const float inverse_z = 1.0f / z;
      screen[i] = SnapVertex(fx * positions(0, i) * inverse_z + cx, fy * positions(1, i) * inverse_z + cy, z);
    }
  }
  const Eigen::Vector3i* triangles = model_->all_triangles().data();
  // Skin first: it hides most of the eyeballs, whose pixels then fail the depth test early.
  for (int part = 0; part < kNumParts; ++part) {
    const int first = model_->triangle_offset(part);
    const int count = model_->triangle_offset(part + 1) - first;
    out.part_offsets[part] = first;
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
    out.visibility.Draw(screen_.data(), triangles + first, count, first, window);
  }
  out.part_offsets[kNumParts] = model_->triangle_offset(kNumParts);
  out.visibility.CollectCovered(out.foreground);
}

void Renderer::ComposeSkinTexture(const Parameters& phi) {
  const Eigen::Matrix<double, kNumTextureModes, 1> tau = phi.texture();
  if (composed_ && tau == composed_for_) return;
  model_->skin_texture().Compose(tau.data(), skin_ahead_, skin_down_);
  composed_for_ = tau;
  composed_ = true;
}

// What shading one render needs, gathered once.
struct Renderer::ShadingInputs {
  RgbaTexture::Level skin_ahead;
  RgbaTexture::Level skin_down;
  RgbaTexture::Level eyeball;
  float blend;
  Eigen::Vector3f iris, sclera;
  Eigen::Vector4f upper_lid[2], lower_lid[2];
  EyeballShading shading;
};

void Renderer::ShadePixel(const ShadingInputs& in, int index, RenderBuffers& out) const {
  const VisibilityBuffer& vis = out.visibility;
  const int pixel = out.foreground[index];
  const int part = out.PartAt(pixel);
  const Eigen::Vector3i& t = model_->all_triangles()[vis.triangle(pixel)];
  const float b1 = vis.b1(pixel), b2 = vis.b2(pixel), b0 = 1.0f - b1 - b2;
  const Attributes a = b0 * attributes_.col(t[0]) + b1 * attributes_.col(t[1]) + b2 * attributes_.col(t[2]);
  Eigen::Vector3f albedo;
  if (!IsEyeball(part)) {
    albedo = in.skin_ahead.Sample(a[0], a[1]).head<3>();
    if (in.blend > 0) albedo += in.blend * (in.skin_down.Sample(a[0], a[1]).head<3>() - albedo);
  } else {
    const Eigen::Vector4f base = in.eyeball.Sample(a[0], a[1]);
    const float w = base[3];
    // Ambient occlusion: darker toward the lid margins, in the eyeball's angular frame.
    const int eye = EyeOfPart(part);
    const float below_upper = std::max(0.0f, Cubic(in.upper_lid[eye], a[5]) - a[6]);
    const float above_lower = std::max(0.0f, a[6] - Cubic(in.lower_lid[eye], a[5]));
    const float occlusion = Occlusion(below_upper, in.shading.upper_lid_occlusion, in.shading.occlusion_width_rad) *
                            Occlusion(above_lower, in.shading.lower_lid_occlusion, in.shading.occlusion_width_rad);
    albedo = base.head<3>().cwiseProduct(w * in.iris + (1 - w) * in.sclera) * occlusion;
  }
  out.colour.row(index) = albedo.cwiseProduct(a.segment<3>(2)).transpose();
}

void Renderer::Shade(const Parameters& phi, const Camera& camera, RenderBuffers& out) {
  ComposeSkinTexture(phi);
  // Per-vertex attributes: texture coordinates, Lambertian light, and the
  // eyeball's angular coordinates.
  const Eigen::Vector3f light = phi.LightDirection().cast<float>();
  const Eigen::Vector3f ambient = phi.ambient().cast<float>();
  const Eigen::Vector3f light_colour = phi.light_colour().cast<float>();
  for (int part = 0; part < kNumParts; ++part) {
    const PosedPart& posed = posed_.parts[part];
    const int offset = model_->vertex_offset(part);
    for (Eigen::Index i = 0; i < posed.normals.cols(); ++i) {
      auto a = attributes_.col(offset + i);
      a.head<2>() = posed.uvs.col(i);
      a.segment<3>(2) = ambient + light_colour * std::max(0.0f, posed.normals.col(i).dot(light));
      if (IsEyeball(part)) a.segment<2>(5) = model_->eyeball_angles().col(i);
    }
  }

  ShadingInputs in;
  // Mip levels that keep texels about a pixel in size.
  const float pixels_per_mm = static_cast<float>(camera.fx / std::max(posed_.eyes[0].centre.z(), 1.0));
  const int skin_level = skin_ahead_.LevelFor(kSkinTexelsPerMm / pixels_per_mm);
  in.skin_ahead = skin_ahead_.level(skin_level);
  in.skin_down = skin_down_.level(skin_level);
  const RgbaTexture& eyeball = model_->eyeball_texture();
  in.eyeball = eyeball.level(eyeball.LevelFor(eyeball.size() * kEyeballUvPerMm / pixels_per_mm));
  in.blend = posed_.look_down_blend;
  in.iris = phi.iris_colour().cast<float>();
  in.sclera = phi.sclera_tint().cast<float>();
  for (int eye = 0; eye < 2; ++eye) {
    in.upper_lid[eye] = posed_.eyes[eye].upper_lid.cast<float>();
    in.lower_lid[eye] = posed_.eyes[eye].lower_lid.cast<float>();
  }
  in.shading = eyeball_shading_;

  out.colour.resize(static_cast<Eigen::Index>(out.foreground.size()), 3);
  for (int i = 0; i < static_cast<int>(out.foreground.size()); ++i) ShadePixel(in, i, out);
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
    const Eigen::Vector3i t = model.all_triangles()[vis.triangle(pixel)].array() - model.vertex_offset(part);
    const float b1 = vis.b1(pixel), b2 = vis.b2(pixel), b0 = 1.0f - b1 - b2;
    float* out = data + static_cast<std::size_t>(pixel) * channels;
    for (int c = 0; c < channels; ++c) out[c] = b0 * values(c, t[0]) + b1 * values(c, t[1]) + b2 * values(c, t[2]);
  }
  return field;
}

}  // namespace gazedirector
