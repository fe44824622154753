#include "gazedirector/model/eye_region_model.h"

#include <array>
#include <map>
#include <set>
#include <cmath>
#include <future>

#include <Eigen/Dense>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "gazedirector/geometry/rotation.h"
#include "gazedirector/io/obj_reader.h"
#include "gazedirector/model/eye_region_topology.h"
#include "gazedirector/util/simd.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace fs = std::filesystem;
namespace {

constexpr int kEyeballTextureSize = 512;

// The subdivided skin's positions and unit normals, out of its packed
// columns (x, y, z, nx, ny, nz and two unused floats per vertex). With AVX2,
// eight vertices at a time: one square root and three divisions per eight
// vertices instead of per vertex, each lane computed as Eigen's normalized()
// computes it here (its squared norm nx² + (ny² + nz²), contracted), so the
// results are the same.
void UnpackSkin(const Eigen::Matrix<float, 8, Eigen::Dynamic>& fine, Eigen::Matrix3Xf& positions,
                Eigen::Matrix3Xf& normals) {
  const int count = static_cast<int>(fine.cols());
  positions.resize(3, count);
  normals.resize(3, count);
  int i = 0;
#if defined(__AVX2__) && defined(__FMA__)
  for (; i + 8 <= count; i += 8) {
    const float* p = fine.data() + 8 * static_cast<std::ptrdiff_t>(i);
    // Each column's two halves, vertex k in the low 128-bit lanes and k + 4 in the high.
    auto half = [&](int k, int h) { return _mm256_loadu2_m128(p + 8 * (k + 4) + 4 * h, p + 8 * k + 4 * h); };
    const simd::Channels front = simd::Transpose(half(0, 0), half(1, 0), half(2, 0), half(3, 0));  // x y z nx
    const simd::Channels back = simd::Transpose(half(0, 1), half(1, 1), half(2, 1), half(3, 1));   // ny nz - -
    const __m256 nx = front.w, ny = back.x, nz = back.y;
    const __m256 squared = _mm256_fmadd_ps(nx, nx, _mm256_fmadd_ps(nz, nz, _mm256_mul_ps(ny, ny)));
    const __m256 length = _mm256_sqrt_ps(squared);
    const __m256 positive = _mm256_cmp_ps(squared, _mm256_setzero_ps(), _CMP_GT_OQ);
    auto unit = [&](__m256 v) { return _mm256_blendv_ps(v, _mm256_div_ps(v, length), positive); };
    const std::ptrdiff_t out = 3 * static_cast<std::ptrdiff_t>(i);
    simd::StoreTriples(front.x, front.y, front.z, positions.data() + out);
    simd::StoreTriples(unit(nx), unit(ny), unit(nz), normals.data() + out);
  }
#endif
  for (; i < count; ++i) {
    positions.col(i) = fine.col(i).head<3>();
    normals.col(i) = fine.col(i).segment<3>(3).normalized();
  }
}

std::vector<Eigen::Vector3i> Rewound(std::vector<Eigen::Vector3i> triangles) {
  for (Eigen::Vector3i& t : triangles) std::swap(t[1], t[2]);
  return triangles;
}

// The eyeball colour map with the iris desaturated to its luminance: the
// fitted iris colour τ_iris supplies the hue.
RgbaTexture LoadEyeballTexture(const fs::path& path) {
  cv::Mat bgr = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (bgr.empty()) Fail(ExitCode::kAssets, "cannot read the eyeball texture {}", path.string());
  cv::resize(bgr, bgr, cv::Size(kEyeballTextureSize, kEyeballTextureSize), 0, 0, cv::INTER_AREA);
  RgbaTexture texture(kEyeballTextureSize);
  float* out = texture.data();
  const double iris_radius_px = topology::kLimbusUvRadius * kEyeballTextureSize;
  for (int y = 0; y < kEyeballTextureSize; ++y) {
    for (int x = 0; x < kEyeballTextureSize; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      const float r = p[2] / 255.0f, g = p[1] / 255.0f, b = p[0] / 255.0f;
      const double distance = std::hypot(x + 0.5 - 0.5 * kEyeballTextureSize, y + 0.5 - 0.5 * kEyeballTextureSize);  // texels
      const float iris = static_cast<float>(std::clamp((iris_radius_px + 2.0 - distance) / 4.0, 0.0, 1.0));
      const float luminance = 0.299f * r + 0.587f * g + 0.114f * b;
      float* texel = out + (static_cast<std::size_t>(y) * kEyeballTextureSize + x) * 4;
      texel[0] = iris * luminance + (1 - iris) * r;
      texel[1] = iris * luminance + (1 - iris) * g;
      texel[2] = iris * luminance + (1 - iris) * b;
      texel[3] = iris;
    }
  }
  texture.BuildMips();
  return texture;
}

constexpr int kLidCurvePoints = 2 + static_cast<int>(topology::kUpperMargin.size());
static_assert(topology::kUpperMargin.size() == topology::kLowerMargin.size());

// Least-squares cubic y(x) through the points (fixed size: no allocation).
Eigen::Vector4d FitCubic(const std::array<Eigen::Vector2d, kLidCurvePoints>& points) {
  Eigen::Matrix4d normal = 1e-6 * Eigen::Matrix4d::Identity();  // a touch of ridge for nearly straight lids
  Eigen::Vector4d rhs = Eigen::Vector4d::Zero();
  for (const Eigen::Vector2d& p : points) {
    const double x = p.x();
    const Eigen::Vector4d row(1, x, x * x, x * x * x);
    normal += row * row.transpose();
    rhs += row * p.y();
  }
  return normal.ldlt().solve(rhs);
}

// The vertices on boundary edges (used by one triangle) near the eyeball: the
// rim of the eye opening, as opposed to the outer border of the region.
std::vector<int> OpeningRim(const Eigen::Matrix3Xd& positions, const std::vector<Eigen::Vector3i>& triangles) {
  std::map<std::pair<int, int>, int> edge_uses;
  for (const Eigen::Vector3i& t : triangles) {
    for (int k = 0; k < 3; ++k) edge_uses[std::minmax(t[k], t[(k + 1) % 3])]++;
  }
  std::set<int> rim;
  for (const auto& [edge, uses] : edge_uses) {
    if (uses != 1) continue;
    for (int v : {edge.first, edge.second}) {
      if (positions.col(v).norm() < 2.0 * topology::kScleraRadiusMm) rim.insert(v);
    }
  }
  if (rim.size() < 8) Fail(ExitCode::kAssets, "the eye region mesh has no eye opening");
  return {rim.begin(), rim.end()};
}

}  // namespace

Eigen::Matrix3d EyeRegionModel::ModelToHead(int eye) {
  Eigen::Matrix3d m;
  m << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  if (eye == kRightEye) m.col(0) *= -1.0;
  return m;
}

Eigen::Matrix3d EyeRegionModel::GazeRotation(double pitch_deg, double yaw_deg) {
  // Fick gimbal in the head frame: yaw about the vertical axis after pitch.
  return (Eigen::AngleAxisd(-DegToRad(yaw_deg), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(-DegToRad(pitch_deg), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d EyeRegionModel::GazeInHead(double pitch_deg, double yaw_deg) {
  return GazeRotation(pitch_deg, yaw_deg) * Eigen::Vector3d(0, 0, -1);
}

Eigen::Vector2d EyeRegionModel::PitchYawInHead(const Eigen::Vector3d& direction) {
  const Eigen::Vector3d u = direction.normalized();
  return {RadToDeg(std::asin(std::clamp(-u.y(), -1.0, 1.0))), RadToDeg(std::atan2(u.x(), -u.z()))};
}

Eigen::Vector2d EyeRegionModel::CameraGazeInHead(double pitch_deg, double yaw_deg, double head_yaw_deg) {
  const Eigen::Matrix3d head = RotationFromEulerXYZ(Eigen::Vector3d(0, DegToRad(head_yaw_deg), 0));
  return PitchYawInHead(head.transpose() * GazeInHead(pitch_deg, yaw_deg));
}

double EyeRegionModel::EyeYaw(const Parameters& phi, int eye) {
  // The left eye sits at +x; converging turns it toward -x (smaller yaw).
  return eye == kLeftEye ? phi.gaze_yaw() - 0.5 * phi.vergence() : phi.gaze_yaw() + 0.5 * phi.vergence();
}

Eigen::Vector3d EyeRegionModel::EyeCentreInHead(const Parameters& phi, int eye) {
  return Eigen::Vector3d(eye == kLeftEye ? 0.5 * phi.interocular() : -0.5 * phi.interocular(), 0, 0);
}

Eigen::Vector3d EyeRegionModel::PointInHead(const Parameters& phi, const Eigen::Vector3d& point) {
  return phi.rotation().transpose() * (point - phi.translation());
}

Eigen::Vector3d EyeRegionModel::FixationAngles(const Parameters& phi, const Eigen::Vector3d& point) {
  const Eigen::Vector3d in_head = PointInHead(phi, point);
  const Eigen::Vector2d left = PitchYawInHead(in_head - EyeCentreInHead(phi, kLeftEye));
  const Eigen::Vector2d right = PitchYawInHead(in_head - EyeCentreInHead(phi, kRightEye));
  // Wrapped: behind the eyes one eye's yaw reads near +180 and the other's
  // near -180, and their plain mean would face away from the point.
  const double vergence = std::remainder(right.y() - left.y(), 360.0);
  return Eigen::Vector3d(0.5 * (left.x() + right.x()), std::remainder(left.y() + 0.5 * vergence, 360.0), vergence);
}

std::shared_ptr<const EyeRegionModel> EyeRegionModel::Load(const Assets& assets) {
  auto model = std::make_shared<EyeRegionModel>();
  const fs::path root = assets.eye_model();
  // Decoded beside the rest (a fifth of the load's time on its own).
  std::future<RgbaTexture> eyeball_texture =
      std::async(std::launch::async, LoadEyeballTexture, root / "textures" / "iris" / "eyeball_grey.png");
  model->shape_ = ShapeModel::Load(root / "shape", kNumShapeModes);
  if (model->shape_.num_vertices() != topology::kNumRegionVertices) {
    Fail(ExitCode::kAssets, "{}: the shape model has {} vertices, not {}", root.string(), model->shape_.num_vertices(),
         topology::kNumRegionVertices);
  }
  model->subdivision_ = Subdivision::Load(root / "subdivision", "eye_region", topology::kNumRegionVertices);
  const ObjMesh region = ReadObj(root / "mesh" / "eye_region.obj");
  if (static_cast<int>(region.positions.size()) != topology::kNumRegionVertices || region.uvs.empty()) {
    Fail(ExitCode::kAssets, "{}: not the 229-vertex eye region mesh", (root / "mesh" / "eye_region.obj").string());
  }
  Eigen::Matrix2Xd base_uvs(2, topology::kNumRegionVertices);
  for (int i = 0; i < topology::kNumRegionVertices; ++i) base_uvs.col(i) = region.uvs[i];
  model->subdivision_.Apply(base_uvs, model->skin_uvs_);

  // Wind the skin so that normals point out of the face (-y in the model frame).
  Eigen::Matrix3Xd subdivided;
  model->subdivision_.Apply(model->shape_.mean(), subdivided);
  std::vector<Eigen::Vector3i> skin = model->subdivision_.triangles();
  OrientTriangles(subdivided, skin, Eigen::Vector3d(0, -1, 0), /*radial=*/false);
  model->triangles_[kLeftSkin] = skin;
  model->triangles_[kRightSkin] = Rewound(skin);
  model->opening_rim_ = OpeningRim(subdivided, skin);

  model->base_triangles_ = region.triangles;
  OrientTriangles(model->shape_.mean(), model->base_triangles_, Eigen::Vector3d(0, -1, 0), /*radial=*/false);

  model->eyeball_ = EyeballModel::Load(root / "mesh" / "eyeball.obj");
  model->triangles_[kLeftEyeball] = model->eyeball_.triangles();
  model->triangles_[kRightEyeball] = Rewound(model->eyeball_.triangles());
  model->eyeball_angles_ = model->eyeball_.angles().cast<float>();
  model->eyeball_positions_ = model->eyeball_.positions().cast<float>();
  model->eyeball_normals_ = model->eyeball_.normals().cast<float>();
  for (int part = 0; part < kNumParts; ++part) {
    model->vertex_offsets_[part + 1] = model->vertex_offsets_[part] + model->num_vertices(part);
    model->triangle_offsets_[part + 1] = model->triangle_offsets_[part] + static_cast<int>(model->triangles_[part].size());
    for (const Eigen::Vector3i& t : model->triangles_[part]) {
      model->all_triangles_.push_back(t.array() + model->vertex_offsets_[part]);
    }
  }

  model->skin_texture_ =
      SkinTextureModel::LoadOrBuild(root / "textures" / "skin", Assets::CacheDir(), kNumTextureModes);
  // Each mode alone (the mean subtracted): compose unit coefficients against zero.
  {
    RgbaTexture mean_ahead, mean_down, ahead, down;
    std::vector<double> tau(kNumTextureModes, 0.0);
    model->skin_texture_.Compose(tau.data(), mean_ahead, mean_down);
    for (int j = 0; j < kNumTextureModes; ++j) {
      std::fill(tau.begin(), tau.end(), 0.0);
      tau[j] = 1.0;
      model->skin_texture_.Compose(tau.data(), ahead, down);
      for (RgbaTexture* variant : {&ahead, &down}) {
        const RgbaTexture& mean = variant == &ahead ? mean_ahead : mean_down;
        for (int level = 0; level < variant->num_levels(); ++level) {
          const std::size_t values = static_cast<std::size_t>(variant->size(level)) * variant->size(level) * 4;
          for (std::size_t i = 0; i < values; ++i) variant->data(level)[i] -= mean.data(level)[i];
        }
        model->texture_modes_.push_back(*variant);
      }
    }
  }
  model->eyeball_texture_ = eyeball_texture.get();
  return model;
}

void EyeRegionModel::Pose(const Parameters& phi, PosedModel& posed, PoseWorkspace& work) const {
  const Eigen::Matrix3d rotation = phi.rotation();
  const Eigen::Vector3d translation = phi.translation();
  // Most renders of a fit change other parameters than the shape.
  const auto beta = phi.shape();
  if (work.shape_for.size() != beta.size() || work.shape_for != beta) {
    shape_.Evaluate(beta.data(), work.shape);
    work.shape_for = beta;
  }
  posed.look_down_blend = static_cast<float>(LookDownBlend(phi.eyelid_pitch()));

  for (int eye = 0; eye < 2; ++eye) {
    const Eigen::Matrix3d model_to_head = ModelToHead(eye);
    const Eigen::Matrix3d gaze_head = GazeRotation(phi.gaze_pitch(), EyeYaw(phi, eye));
    // The gaze rotation seen in this eye's model frame (ModelToHead is orthogonal).
    const Eigen::Matrix3d gaze_model = model_to_head.transpose() * gaze_head * model_to_head;
    PosedEye& state = posed.eyes[eye];
    // The region's frame in the camera's; its origin is the eyeball's centre.
    state.region_to_camera = rotation * model_to_head;
    state.centre = rotation * EyeCentreInHead(phi, eye) + translation;
    state.eyeball_to_camera = rotation * gaze_head * model_to_head;
    state.gaze = rotation * gaze_head * Eigen::Vector3d(0, 0, -1);

    PoseSkin(phi, gaze_model, state, posed.parts[SkinPart(eye)], work);
    posed.region[eye] = work.rigged;
    PoseEyeball(phi.iris_size(), state, posed.parts[EyeballPart(eye)], work);
    FitLidMargins(gaze_model, work.rigged, state);
  }
}

void EyeRegionModel::PoseSkin(const Parameters& phi, const Eigen::Matrix3d& gaze_model, const PosedEye& eye,
                              PosedPart& skin, PoseWorkspace& work) const {
  // Rig the lids, then place in the camera frame and subdivide.
  work.rigged = work.shape;
  rig_.Apply(phi.eyelid_pitch(), phi.eyelid_closure(), gaze_model * Eigen::Vector3d(0, -1, 0), work.rigged);
  // Normals of the coarse mesh, subdivided like the positions: a quarter of
  // the cross products of the fine mesh, and as smooth.
  VertexNormals(work.rigged, base_triangles_, work.normals);
  // Placed in the camera frame before subdividing, where there are a quarter
  // as many vertices: subdivision is affine (each fine vertex's weights sum to 1).
  work.coarse.resize(8, work.rigged.cols());
  for (Eigen::Index i = 0; i < work.rigged.cols(); ++i) {
    work.coarse.col(i) << (eye.region_to_camera * work.rigged.col(i) + eye.centre).cast<float>(),
        (eye.region_to_camera * work.normals.col(i)).cast<float>(), 0.0f, 0.0f;
  }
  subdivision_.Apply(work.coarse, work.fine);
  UnpackSkin(work.fine, skin.positions, skin.normals);
  if (skin.uvs.cols() != skin_uvs_.cols()) skin.uvs = skin_uvs_.cast<float>();
}

void EyeRegionModel::PoseEyeball(double iris_size, const PosedEye& eye, PosedPart& ball, PoseWorkspace& work) const {
  // Rotated by the gaze about its centre.
  const Eigen::Matrix3f eyeball_to_camera = eye.eyeball_to_camera.cast<float>();
  ball.positions.noalias() = eyeball_to_camera * eyeball_positions_;
  ball.positions.colwise() += eye.centre.cast<float>();
  ball.normals.noalias() = eyeball_to_camera * eyeball_normals_;
  // Texture coordinates: the sclera's depend only on the iris size (kept
  // from the last pose when it has not changed), the cornea's on the view.
  if (work.remapped_iris_size != iris_size) {
    const int vertices = eyeball_.num_vertices();
    work.remapped_uvs.resize(2, vertices);
    for (int i = 0; i < vertices; ++i) {
      work.remapped_uvs.col(i) = EyeballModel::RemapForIrisSize(eyeball_.uvs().col(i), iris_size).cast<float>();
    }
    work.remapped_iris_size = iris_size;
  }
  ball.uvs = work.remapped_uvs;
  eyeball_.RefractedUvs(eye.CameraInEyeball(), iris_size, ball.uvs);
}

void EyeRegionModel::FitLidMargins(const Eigen::Matrix3d& gaze_model, const Eigen::Matrix3Xd& rigged, PosedEye& eye) {
  // The margins' vertices in the eyeball's angular coordinates.
  std::array<Eigen::Vector2d, kLidCurvePoints> upper, lower;
  auto angles_of = [&](int vertex) {
    return EyeballModel::AnglesOf((gaze_model.transpose() * rigged.col(vertex)).normalized());
  };
  upper.front() = lower.front() = angles_of(topology::kInnerCorner);
  upper.back() = lower.back() = angles_of(topology::kOuterCorner);
  for (std::size_t i = 0; i < topology::kUpperMargin.size(); ++i) {
    upper[i + 1] = angles_of(topology::kUpperMargin[i]);
    lower[i + 1] = angles_of(topology::kLowerMargin[i]);
  }
  eye.upper_lid = FitCubic(upper);
  eye.lower_lid = FitCubic(lower);
}

}  // namespace gazedirector
