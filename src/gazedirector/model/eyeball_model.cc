#include "gazedirector/model/eyeball_model.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <utility>

#include "gazedirector/io/obj_reader.h"
#include "gazedirector/model/eye_region_topology.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace {

constexpr double kCorneaRefractiveIndex = 1.376;
// The iris lies a little behind the limbus ring.
constexpr double kIrisPlaneDepthMm = topology::kLimbusDepthMm - 0.3;
constexpr double kScleraUvEdge = 0.45;  // where the stretched sclera meets the unchanged layout

// For each vertex, the vertex at its mirror image (coordinates scaled by
// `flip`); the mesh must be symmetric to within 0.01 mm.
std::vector<int> MirrorVertices(const Eigen::Matrix3Xd& positions, const Eigen::Vector3d& flip,
                                const std::filesystem::path& obj) {
  std::vector<int> mirrored(static_cast<std::size_t>(positions.cols()));
  for (Eigen::Index i = 0; i < positions.cols(); ++i) {
    Eigen::Index nearest = 0;
    (positions.colwise() - positions.col(i).cwiseProduct(flip)).colwise().squaredNorm().minCoeff(&nearest);
    if ((positions.col(nearest) - positions.col(i).cwiseProduct(flip)).norm() > 0.01) {
      Fail(ExitCode::kAssets, "{}: the eyeball mesh is not symmetric (vertex {})", obj.string(), i);
    }
    mirrored[static_cast<std::size_t>(i)] = static_cast<int>(nearest);
  }
  return mirrored;
}

// Cells per side of each cube face that patches the eyeball: the front face's
// 4 x 4 cells hold 7-83 triangles each.
constexpr int kPatchCells = 4;
// Patches are culled as facing away only beyond this angle (about 3 degrees)
// past the silhouette: snapping to the subpixel grid can turn a triangle
// seen edge-on.
constexpr double kFacingMargin = 0.05;

// Orders `triangles` by the cube map cell of their centroids' directions and
// returns the patches, each with its bounds.
std::vector<EyeballPatch> SortIntoPatches(const Eigen::Matrix3Xd& positions, std::vector<Eigen::Vector3i>& triangles) {
  auto face_normal = [&](const Eigen::Vector3i& t) {
    return Eigen::Vector3d((positions.col(t[1]) - positions.col(t[0])).cross(positions.col(t[2]) - positions.col(t[0])).normalized());
  };
  auto cell = [&](const Eigen::Vector3i& t) {
    const Eigen::Vector3d g = positions.col(t[0]) + positions.col(t[1]) + positions.col(t[2]);  // 3 x the centroid
    Eigen::Index axis;
    g.cwiseAbs().maxCoeff(&axis);
    int key = 2 * static_cast<int>(axis) + (g[axis] > 0);
    for (int k = 0; k < 3; ++k) {
      if (k == axis) continue;
      const double along = (g[k] / std::abs(g[axis]) + 1) / 2;  // [0, 1] across the face
      key = key * kPatchCells + std::clamp(static_cast<int>(along * kPatchCells), 0, kPatchCells - 1);
    }
    return key;
  };
  std::vector<std::pair<int, Eigen::Vector3i>> keyed;
  for (const Eigen::Vector3i& t : triangles) keyed.emplace_back(cell(t), t);
  std::stable_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t i = 0; i < keyed.size(); ++i) triangles[i] = keyed[i].second;
  std::vector<EyeballPatch> patches;
  for (int begin = 0; begin < static_cast<int>(keyed.size());) {
    int end = begin;
    while (end < static_cast<int>(keyed.size()) && keyed[end].first == keyed[begin].first) ++end;
    EyeballPatch patch;
    patch.begin = begin, patch.end = end;
    Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
    for (int i = begin; i < end; ++i) {
      const Eigen::Vector3i& t = triangles[i];
      for (int k = 0; k < 3; ++k) patch.centre += positions.col(t[k]) / (3.0 * (end - begin));
      normal_sum += face_normal(t);
    }
    patch.axis = normal_sum.normalized();
    double widest_cosine = 1, radius_squared = 0;
    for (int i = begin; i < end; ++i) {
      const Eigen::Vector3i& t = triangles[i];
      for (int k = 0; k < 3; ++k) {
        radius_squared = std::max(radius_squared, (positions.col(t[k]) - patch.centre).squaredNorm());
      }
      widest_cosine = std::min(widest_cosine, face_normal(t).dot(patch.axis));
    }
    patch.radius = std::sqrt(radius_squared);
    patch.cone_sine = widest_cosine > 0 ? std::sqrt(1 - widest_cosine * widest_cosine) : 2.0;
    patches.push_back(patch);
    begin = end;
  }
  return patches;
}

}  // namespace

bool EyeballPatch::FacesAwayFrom(const Eigen::Vector3d& camera) const {
  // Every point p of the ball sees the camera from behind every normal n of
  // the cone when the angle between the axis and p - camera stays below
  // 90 degrees less the cone's: a.(c - camera) - r > sin(cone) |c - camera| + r.
  const double sine = cone_sine + kFacingMargin;
  if (sine >= 1) return false;
  const Eigen::Vector3d view = centre - camera;
  return axis.dot(view) - radius > sine * (view.norm() + radius);
}

int OrientTriangles(const Eigen::Matrix3Xd& positions, std::vector<Eigen::Vector3i>& triangles,
                    const Eigen::Vector3d& outward_hint, bool radial) {
  int flipped = 0;
  for (Eigen::Vector3i& t : triangles) {
    const Eigen::Vector3d a = positions.col(t[0]), b = positions.col(t[1]), c = positions.col(t[2]);
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    const Eigen::Vector3d outward = radial ? Eigen::Vector3d((a + b + c) / 3.0) : outward_hint;
    if (normal.dot(outward) < 0) {
      std::swap(t[1], t[2]);
      ++flipped;
    }
  }
  return flipped;
}

void VertexNormals(const Eigen::Matrix3Xd& positions, const std::vector<Eigen::Vector3i>& triangles,
                   Eigen::Matrix3Xd& normals) {
  normals.setZero(3, positions.cols());
  for (const Eigen::Vector3i& t : triangles) {
    const Eigen::Vector3d n = (positions.col(t[1]) - positions.col(t[0])).cross(positions.col(t[2]) - positions.col(t[0]));
    for (int k = 0; k < 3; ++k) normals.col(t[k]) += n;
  }
  for (int i = 0; i < normals.cols(); ++i) {
    const double length = normals.col(i).norm();
    if (length > 0) normals.col(i) /= length;
  }
}

Eigen::Vector2d EyeballModel::AnglesOf(const Eigen::Vector3d& d) {
  return {std::atan2(d.x(), -d.y()), std::atan2(d.z(), std::hypot(d.x(), d.y()))};
}

EyeballModel EyeballModel::Load(const std::filesystem::path& obj) {
  ObjMesh mesh = ReadObj(obj);
  if (mesh.uvs.empty() || mesh.positions.size() < 200) Fail(ExitCode::kAssets, "{}: not the eyeball mesh", obj.string());
  EyeballModel model;
  const int n = static_cast<int>(mesh.positions.size());
  model.positions_ = mesh.PositionsMm();
  model.uvs_.resize(2, n);
  model.angles_.resize(2, n);
  for (int i = 0; i < n; ++i) {
    model.uvs_.col(i) = mesh.uvs[i];
    model.angles_.col(i) = AnglesOf(model.positions_.col(i).normalized());
  }
  for (int index : topology::kLimbus) {
    if (index >= n) Fail(ExitCode::kAssets, "{}: limbus vertex {} missing", obj.string(), index);
  }
  model.triangles_ = mesh.triangles;
  OrientTriangles(model.positions_, model.triangles_, Eigen::Vector3d::Zero(), /*radial=*/true);
  model.patches_ = SortIntoPatches(model.positions_, model.triangles_);
  VertexNormals(model.positions_, model.triangles_, model.normals_);

  model.is_cornea_.assign(n, false);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p = model.positions_.col(i);
    const bool in_front = -p.y() >= topology::kLimbusDepthMm - 1e-3;
    const bool inside = std::hypot(p.x(), p.z()) <= topology::kLimbusRadiusMm + 1e-3;
    if (in_front && inside) {
      model.cornea_.push_back(i);
      model.is_cornea_[i] = true;
    }
  }
  if (model.cornea_.size() < 33) Fail(ExitCode::kAssets, "{}: found no cornea in front of the limbus", obj.string());
  const int padded = (static_cast<int>(model.cornea_.size()) + kRefractionLanes - 1) / kRefractionLanes * kRefractionLanes;
  model.cornea_points_.resize(padded, 3);
  model.cornea_normals_.resize(padded, 3);
  for (int k = 0; k < padded; ++k) {
    const int vertex = model.cornea_[std::min<std::size_t>(k, model.cornea_.size() - 1)];
    model.cornea_points_.row(k) = model.positions_.col(vertex).transpose().array();
    model.cornea_normals_.row(k) = model.normals_.col(vertex).transpose().array();
  }
  model.mirrored_x_ = MirrorVertices(model.positions_, Eigen::Vector3d(-1, 1, 1), obj);
  model.mirrored_z_ = MirrorVertices(model.positions_, Eigen::Vector3d(1, 1, -1), obj);
  return model;
}

Eigen::Vector2d EyeballModel::RemapForIrisSize(const Eigen::Vector2d& uv, double iris_size) {
  const Eigen::Vector2d offset = uv - Eigen::Vector2d(0.5, 0.5);
  const double radius = offset.norm();
  const double iris_edge = topology::kLimbusUvRadius * iris_size;
  double remapped;
  if (radius <= iris_edge) {
    remapped = radius / iris_size;
  } else if (radius < kScleraUvEdge) {
    const double t = (radius - iris_edge) / (kScleraUvEdge - iris_edge);
    remapped = topology::kLimbusUvRadius + t * (kScleraUvEdge - topology::kLimbusUvRadius);
  } else {
    return uv;
  }
  return radius > 0 ? Eigen::Vector2d(Eigen::Vector2d(0.5, 0.5) + offset * (remapped / radius)) : uv;
}

void EyeballModel::RefractedUvs(const Eigen::Vector3d& camera, double iris_size, Eigen::Matrix2Xf& uvs) const {
  using Lanes = Eigen::Array<double, kRefractionLanes, 1>;
  const double eta = 1.0 / kCorneaRefractiveIndex;
  const double uv_per_mm = topology::kLimbusUvRadius / (topology::kLimbusRadiusMm * iris_size);
  const int count = static_cast<int>(cornea_.size());
  for (int first = 0; first < count; first += kRefractionLanes) {
    auto point = [&](int axis) { return cornea_points_.col(axis).segment<kRefractionLanes>(first); };
    auto normal = [&](int axis) { return cornea_normals_.col(axis).segment<kRefractionLanes>(first); };
    // As RefractedUv, a lane per vertex.
    Lanes vx = point(0) - camera.x(), vy = point(1) - camera.y(), vz = point(2) - camera.z();
    const Lanes inverse_length = (vx.square() + vy.square() + vz.square()).sqrt().inverse();
    vx *= inverse_length, vy *= inverse_length, vz *= inverse_length;
    const Lanes cos_in = (-(normal(0) * vx + normal(1) * vy + normal(2) * vz)).max(0.0).min(1.0);
    const Lanes k = 1.0 - eta * eta * (1.0 - cos_in.square());
    const Lanes along_normal = eta * cos_in - k.max(0.0).sqrt();
    Lanes rx = eta * vx + along_normal * normal(0), ry = eta * vy + along_normal * normal(1),
          rz = eta * vz + along_normal * normal(2);
    const Lanes inverse_refracted = (rx.square() + ry.square() + rz.square()).sqrt().inverse();
    rx *= inverse_refracted, ry *= inverse_refracted, rz *= inverse_refracted;
    const Lanes travel = (ry > 1e-6).select((-kIrisPlaneDepthMm - point(1)) / ry, 0.0);
    const Lanes u = 0.5 + (point(0) + rx * travel) * uv_per_mm, v = 0.5 + (point(2) + rz * travel) * uv_per_mm;
    for (int lane = 0; lane < std::min(kRefractionLanes, count - first); ++lane) {
      uvs.col(cornea_[first + lane]) = Eigen::Vector2f(static_cast<float>(u[lane]), static_cast<float>(v[lane]));
    }
  }
}

Eigen::Vector2d EyeballModel::RefractedUv(int vertex, const Eigen::Vector3d& view, double iris_size) const {
  const Eigen::Vector3d p = positions_.col(vertex);
  const Eigen::Vector3d n = normals_.col(vertex);
  const double eta = 1.0 / kCorneaRefractiveIndex;
  const double cos_in = std::clamp(-n.dot(view), 0.0, 1.0);
  const double k = 1.0 - eta * eta * (1.0 - cos_in * cos_in);
  const Eigen::Vector3d refracted = (eta * view + (eta * cos_in - std::sqrt(std::max(k, 0.0))) * n).normalized();
  // March to the iris plane y = -depth (the ray travels toward +y, into the eye).
  Eigen::Vector3d hit = p;
  if (refracted.y() > 1e-6) hit = p + refracted * ((-kIrisPlaneDepthMm - p.y()) / refracted.y());
  const Eigen::Vector2d on_iris(hit.x(), hit.z());
  return Eigen::Vector2d(0.5, 0.5) + on_iris * (topology::kLimbusUvRadius / (topology::kLimbusRadiusMm * iris_size));
}

}  // namespace gazedirector
