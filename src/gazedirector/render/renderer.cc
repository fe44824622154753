#include "gazedirector/render/renderer.h"

#include <algorithm>
#include <cmath>

#include "gazedirector/model/eye_region_topology.h"

namespace gazedirector {
namespace {

// Texels per millimetre of the textures at level 0, measured on the model:
// the skin map spans about 70 mm of face; the eyeball's limbus (5.87 mm) is
// 0.1385 of its uv width.
constexpr float kSkinTexelsPerMm = SkinTextureModel::kSize / 70.0f;
constexpr float kEyeballTexelsPerMmPerSize = topology::kLimbusUvRadius / topology::kLimbusRadiusMm;
constexpr float kIrisEdgeHalfWidthUv = 0.004f;

float Cubic(const Eigen::Vector4d& c, float x) {
  return static_cast<float>(c[0] + x * (c[1] + x * (c[2] + x * c[3])));
}

}  // namespace

int RenderBuffers::PartAt(int pixel) const {
  const int32_t id = visibility.triangle(pixel);
  if (id < 0) return -1;
  for (int p = 0; p < kNumParts; ++p) {
    if (id < part_offsets[p + 1]) return p;
  }
  return -1;
}

cv::Mat RenderBuffers::ColourImage(const cv::Mat& background) const {
  cv::Mat image = background.empty() ? cv::Mat(height(), width(), CV_8UC3, cv::Scalar::all(0)) : background.clone();
  for (int pixel : foreground) {
    const float* rgb = &colour[3 * static_cast<std::size_t>(pixel)];
    image.at<cv::Vec3b>(pixel / width(), pixel % width()) =
        cv::Vec3b(cv::saturate_cast<uchar>(255 * rgb[2]), cv::saturate_cast<uchar>(255 * rgb[1]),
                  cv::saturate_cast<uchar>(255 * rgb[0]));
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

Renderer::Renderer(std::shared_ptr<const EyeRegionModel> model) : model_(std::move(model)) {}

void Renderer::Render(const Parameters& phi, const Camera& camera, RenderBuffers& out) {
  Pose(phi);
  Rasterize(camera, out);
  Shade(phi, camera, out);
}

void Renderer::Pose(const Parameters& phi) { model_->Pose(phi, posed_, workspace_); }

void Renderer::Rasterize(const Camera& camera, RenderBuffers& out) const {
  out.visibility.Reset(camera.width, camera.height);
  const float fx = static_cast<float>(camera.fx), fy = static_cast<float>(camera.fy);
  const float cx = static_cast<float>(camera.cx), cy = static_cast<float>(camera.cy);
  int32_t offset = 0;
  // Skin first: it hides most of the eyeballs, so their pixels fail the depth test early.
  for (int part : {kLeftSkin, kRightSkin, kLeftEyeball, kRightEyeball}) {
    const Eigen::Matrix3Xf& positions = posed_.parts[part].positions;
    std::vector<ScreenVertex>& screen = screen_[part];
    screen.resize(static_cast<std::size_t>(positions.cols()));
    for (Eigen::Index i = 0; i < positions.cols(); ++i) {
      const float z = positions(2, i);
      const float inverse_z = 1.0f / z;
      screen[i] = {fx * positions(0, i) * inverse_z + cx, fy * positions(1, i) * inverse_z + cy, z};
    }
  }
  for (int part = 0; part < kNumParts; ++part) {
    out.part_offsets[part] = offset;
    const auto& triangles = model_->triangles(part);
    out.visibility.Draw(screen_[part].data(), triangles.data(), static_cast<int>(triangles.size()), offset);
    offset += static_cast<int32_t>(triangles.size());
  }
  out.part_offsets[kNumParts] = offset;
  out.visibility.CollectCovered(out.foreground);
}

void Renderer::ComposeSkinTexture(const Parameters& phi) {
  const Eigen::Matrix<double, kNumTextureModes, 1> tau = phi.texture();
  if (composed_ && tau == composed_for_) return;
  model_->skin_texture().Compose(tau.data(), skin_ahead_, skin_down_);
  composed_for_ = tau;
  composed_ = true;
}

void Renderer::Shade(const Parameters& phi, const Camera& camera, RenderBuffers& out) {
  ComposeSkinTexture(phi);
  const Eigen::Vector3f light = phi.LightDirection().cast<float>();
  const Eigen::Vector3f ambient = phi.ambient().cast<float>();
  const Eigen::Vector3f light_colour = phi.light_colour().cast<float>();
  for (int part = 0; part < kNumParts; ++part) {
    const Eigen::Matrix3Xf& normals = posed_.parts[part].normals;
    Eigen::Matrix3Xf& shade = vertex_light_[part];
    shade.resize(3, normals.cols());
    for (Eigen::Index i = 0; i < normals.cols(); ++i) {
      shade.col(i) = ambient + light_colour * std::max(0.0f, normals.col(i).dot(light));
    }
  }

  // Mip levels that keep texels about a pixel in size.
  const float pixels_per_mm = static_cast<float>(camera.fx / std::max(posed_.eyes[0].centre.z(), 1.0));
  const int skin_level = skin_ahead_.LevelFor(kSkinTexelsPerMm / pixels_per_mm);
  const RgbTexture& eyeball_texture = model_->eyeball_texture();
  const int eyeball_level =
      eyeball_texture.LevelFor(eyeball_texture.size() * kEyeballTexelsPerMmPerSize / pixels_per_mm);
  const float blend = posed_.look_down_blend;
  const Eigen::Vector3f iris = phi.iris_colour().cast<float>();
  const Eigen::Vector3f sclera = phi.sclera_tint().cast<float>();
  const Eigen::Matrix2Xd& eyeball_angles = model_->eyeball().angles();
  const float iris_edge = static_cast<float>(topology::kLimbusUvRadius);

  out.colour.resize(3 * static_cast<std::size_t>(out.visibility.size()));
  const VisibilityBuffer& vis = out.visibility;
  for (int pixel : out.foreground) {
    const int part = out.PartAt(pixel);
    const Eigen::Vector3i& t = model_->triangles(part)[vis.triangle(pixel) - out.part_offsets[part]];
    const float b1 = vis.b1(pixel), b2 = vis.b2(pixel), b0 = 1.0f - b1 - b2;
    const PosedPart& posed = posed_.parts[part];
    const Eigen::Vector2f uv = b0 * posed.uvs.col(t[0]) + b1 * posed.uvs.col(t[1]) + b2 * posed.uvs.col(t[2]);
    const Eigen::Vector3f& s0 = vertex_light_[part].col(t[0]);
    const Eigen::Vector3f shade = b0 * s0 + b1 * vertex_light_[part].col(t[1]) + b2 * vertex_light_[part].col(t[2]);
    float albedo[3];
    if (!IsEyeball(part)) {
      float ahead[3], down[3];
      skin_ahead_.Sample(uv.x(), uv.y(), skin_level, ahead);
      if (blend > 0) {
        skin_down_.Sample(uv.x(), uv.y(), skin_level, down);
        for (int c = 0; c < 3; ++c) albedo[c] = ahead[c] + blend * (down[c] - ahead[c]);
      } else {
        std::copy(ahead, ahead + 3, albedo);
      }
    } else {
      float base[3];
      eyeball_texture.Sample(uv.x(), uv.y(), eyeball_level, base);
      const float radius = std::hypot(uv.x() - 0.5f, uv.y() - 0.5f);
      const float w = std::clamp((iris_edge + kIrisEdgeHalfWidthUv - radius) / (2 * kIrisEdgeHalfWidthUv), 0.0f, 1.0f);
      // Ambient occlusion: darker toward the lid margins, in the eyeball's angular frame.
      const PosedEye& eye = posed_.eyes[EyeOfPart(part)];
      const float azimuth = static_cast<float>(b0 * eyeball_angles(0, t[0]) + b1 * eyeball_angles(0, t[1]) + b2 * eyeball_angles(0, t[2]));
      const float elevation = static_cast<float>(b0 * eyeball_angles(1, t[0]) + b1 * eyeball_angles(1, t[1]) + b2 * eyeball_angles(1, t[2]));
      const float below_upper = std::max(0.0f, Cubic(eye.upper_lid, azimuth) - elevation);
      const float above_lower = std::max(0.0f, elevation - Cubic(eye.lower_lid, azimuth));
      const float width = eyeball_shading_.occlusion_width_rad;
      const float occlusion = (1.0f - eyeball_shading_.upper_lid_occlusion * std::exp(-below_upper / width)) *
                              (1.0f - eyeball_shading_.lower_lid_occlusion * std::exp(-above_lower / width));
      for (int c = 0; c < 3; ++c) albedo[c] = base[c] * (w * iris[c] + (1 - w) * sclera[c]) * occlusion;
    }
    float* rgb = &out.colour[3 * static_cast<std::size_t>(pixel)];
    for (int c = 0; c < 3; ++c) rgb[c] = albedo[c] * shade[c];
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
    const Eigen::Vector3i& t = model.triangles(part)[vis.triangle(pixel) - buffers.part_offsets[part]];
    const float b1 = vis.b1(pixel), b2 = vis.b2(pixel), b0 = 1.0f - b1 - b2;
    float* out = data + static_cast<std::size_t>(pixel) * channels;
    for (int c = 0; c < channels; ++c) out[c] = b0 * values(c, t[0]) + b1 * values(c, t[1]) + b2 * values(c, t[2]);
  }
  return field;
}

}  // namespace gazedirector
