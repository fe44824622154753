#pragma once

#include <filesystem>
#include <vector>

#include <Eigen/Core>

namespace gazedirector {

// A patch of the eyeball's surface, for culling its triangles together: the
// triangles [begin, end) of EyeballModel::triangles(), a ball that holds them
// and the cone that holds their outward face normals (eyeball frame, mm).
struct EyeballPatch {
  int begin = 0, end = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0;
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();  // unit
  double cone_sine = 2;  // sine of the widest normal's angle from `axis`; above 1 when one reaches 90 degrees

  // Whether every triangle faces away from a camera at `camera` (eyeball
  // frame), with a margin against the rounding of screen coordinates.
  bool FacesAwayFrom(const Eigen::Vector3d& camera) const;
};

// The two-sphere eyeball mesh (sclera sphere of 12.05 mm and corneal bulge),
// in millimetres, centred at the origin and looking along -y, in the same
// model frame as the eye region (+x toward the outer corner, +z up).
class EyeballModel {
 public:
  static EyeballModel Load(const std::filesystem::path& obj);

  int num_vertices() const { return static_cast<int>(positions_.cols()); }
  const Eigen::Matrix3Xd& positions() const { return positions_; }
  const Eigen::Matrix3Xd& normals() const { return normals_; }
  const Eigen::Matrix2Xd& uvs() const { return uvs_; }
  // Outward-facing, counter-clockwise seen from outside; ordered patch by patch.
  const std::vector<Eigen::Vector3i>& triangles() const { return triangles_; }
  // The surface in patches of neighbouring triangles (a cube map's cells),
  // so that a renderer can skip those facing away or outside the eye opening.
  const std::vector<EyeballPatch>& patches() const { return patches_; }
  // Vertices of the cornea (in front of and inside the limbus), which show
  // the iris through refraction.
  const std::vector<int>& cornea() const { return cornea_; }
  const std::vector<bool>& is_cornea() const { return is_cornea_; }
  // Azimuth (toward +x) and elevation (toward +z) of each vertex about the
  // centre, in radians, 0 straight ahead: the eyeball's own angular
  // coordinates, in which the lid curves for ambient occlusion are fitted.
  const Eigen::Matrix2Xd& angles() const { return angles_; }

  // Texture coordinates for a point of the sclera's uv layout when the iris
  // is `iris_size` times the model's: the iris disc scales, the sclera
  // stretches to meet it.
  static Eigen::Vector2d RemapForIrisSize(const Eigen::Vector2d& uv, double iris_size);

  // The texture coordinates seen through cornea vertex `vertex` along the
  // unit view ray `view` (from the camera toward the vertex, eyeball frame):
  // the ray refracts at the cornea and meets the iris plane.
  Eigen::Vector2d RefractedUv(int vertex, const Eigen::Vector3d& view, double iris_size) const;
  // The same for every cornea vertex seen from `camera` (a point in the
  // eyeball frame), written to the columns cornea() of `uvs`; in vector lanes
  // and without allocating.
  void RefractedUvs(const Eigen::Vector3d& camera, double iris_size, Eigen::Matrix2Xf& uvs) const;

  // The vertex at each vertex's mirror image across the eyeball's vertical
  // plane (x -> -x) or its horizontal plane (z -> -z): the mesh is symmetric
  // about both, so surface hidden on one side can borrow from the other.
  const std::vector<int>& mirrored_across_x() const { return mirrored_x_; }
  const std::vector<int>& mirrored_across_z() const { return mirrored_z_; }

  // Angular coordinates (azimuth, elevation) of a direction in the eyeball frame.
  static Eigen::Vector2d AnglesOf(const Eigen::Vector3d& direction);

 private:
  Eigen::Matrix3Xd positions_;
  Eigen::Matrix3Xd normals_;
  Eigen::Matrix2Xd uvs_;
  Eigen::Matrix2Xd angles_;
  std::vector<Eigen::Vector3i> triangles_;
  std::vector<EyeballPatch> patches_;
  std::vector<int> cornea_;
  // The cornea's positions and normals, one coordinate per column, padded to
  // whole lanes by repeating the last vertex.
  static constexpr int kRefractionLanes = 8;
  Eigen::Array<double, Eigen::Dynamic, 3> cornea_points_, cornea_normals_;
  std::vector<bool> is_cornea_;
  std::vector<int> mirrored_x_;
  std::vector<int> mirrored_z_;
};

// Orients triangles counter-clockwise seen from outside: their normals point
// along `outward_hint`, or away from the origin when `radial`. Returns the
// number flipped.
int OrientTriangles(const Eigen::Matrix3Xd& positions, std::vector<Eigen::Vector3i>& triangles,
                    const Eigen::Vector3d& outward_hint, bool radial);

// Area-weighted vertex normals of a triangle mesh.
void VertexNormals(const Eigen::Matrix3Xd& positions, const std::vector<Eigen::Vector3i>& triangles,
                   Eigen::Matrix3Xd& normals);

}  // namespace gazedirector
