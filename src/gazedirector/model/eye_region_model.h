#pragma once

#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "gazedirector/io/assets.h"
#include "gazedirector/model/eyeball_model.h"
#include "gazedirector/model/eyelid_rig.h"
#include "gazedirector/model/parameters.h"
#include "gazedirector/model/shape_model.h"
#include "gazedirector/model/skin_texture_model.h"
#include "gazedirector/model/subdivision.h"
#include "gazedirector/render/texture.h"

namespace gazedirector {

// The four parts of the model. "Left" and "right" are the subject's: the left
// eye is at +x of the head frame, on the image right of a frontal face.
enum Part : int { kLeftSkin = 0, kRightSkin = 1, kLeftEyeball = 2, kRightEyeball = 3, kNumParts = 4 };
enum Eye : int { kLeftEye = 0, kRightEye = 1 };
inline bool IsEyeball(int part) { return part >= kLeftEyeball; }
inline int EyeOfPart(int part) { return part % 2; }
inline int SkinPart(int eye) { return eye; }
inline int EyeballPart(int eye) { return eye + 2; }

// One part posed in camera coordinates (millimetres).
struct PosedPart {
  Eigen::Matrix3Xf positions;
  Eigen::Matrix3Xf normals;
  Eigen::Matrix2Xf uvs;  // skin texture coordinates, or eyeball texture coordinates (refracted on the cornea)
};

// What the renderer needs of one eye besides its meshes.
struct PosedEye {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // eyeball centre, camera frame, mm
  Eigen::Vector3d gaze = Eigen::Vector3d::UnitZ();   // unit optical axis, camera frame
  Eigen::Matrix3d eyeball_to_camera = Eigen::Matrix3d::Identity();  // eyeball model frame -> camera (mirrored for the right eye)
  // The facial region's model frame -> camera (mirrored for the right eye);
  // its origin is the eyeball centre.
  Eigen::Matrix3d region_to_camera = Eigen::Matrix3d::Identity();
  // The lid margins in the eyeball's angular coordinates: elevation as a
  // cubic in azimuth (radians), for ambient occlusion of the eyeball.
  Eigen::Vector4d upper_lid = Eigen::Vector4d::Zero();
  Eigen::Vector4d lower_lid = Eigen::Vector4d::Zero();

  // Where the camera (the camera frame's origin) is in the eyeball model frame.
  Eigen::Vector3d CameraInEyeball() const { return -(eyeball_to_camera.transpose() * centre); }
};

struct PosedModel {
  std::array<PosedPart, kNumParts> parts;
  std::array<PosedEye, 2> eyes;
  float look_down_blend = 0;
  // The rigged, unsubdivided facial mesh of each eye in its model frame (mm),
  // kept for landmarks and lid curves.
  std::array<Eigen::Matrix3Xd, 2> region;
};

// Scratch space for posing, so that steady-state posing allocates nothing.
struct PoseWorkspace {
  Eigen::Matrix3Xd shape;
  Eigen::VectorXd shape_for;  // the β `shape` was evaluated for (empty before the first)
  Eigen::Matrix3Xd rigged;
  Eigen::Matrix3Xd normals;
  // Position and normal per vertex, padded to 8 floats for vector loads.
  Eigen::Matrix<float, 8, Eigen::Dynamic> coarse;
  Eigen::Matrix<float, 8, Eigen::Dynamic> fine;    // the same, subdivided
  double remapped_iris_size = -1;                  // the iris size remapped_uvs were made for
  Eigen::Matrix2Xf remapped_uvs;                   // eyeball uvs for that iris size
};

// The multi-part eye-region model of the paper: two facial eye regions
// (mirror images sharing PCA shape and texture), two articulated two-sphere
// eyeballs fixed relative to them, eyelids that follow the eyelid pitch, and
// the textures to shade them. Immutable once loaded; share it between threads.
class EyeRegionModel {
 public:
  static std::shared_ptr<const EyeRegionModel> Load(const Assets& assets);

  // Poses every part for Φ (no allocation once `posed` has been used).
  void Pose(const Parameters& phi, PosedModel& posed, PoseWorkspace& workspace) const;

  const ShapeModel& shape_model() const { return shape_; }
  const Subdivision& subdivision() const { return subdivision_; }
  const EyeballModel& eyeball() const { return eyeball_; }
  const EyelidRig& rig() const { return rig_; }
  const SkinTextureModel& skin_texture() const { return skin_texture_; }
  // One unit of texture mode j as a texture with mips (variant 0: looking
  // ahead, 1: looking down), for the analytic derivatives of colour.
  const RgbaTexture& texture_mode(int j, int variant) const { return texture_modes_[2 * j + variant]; }
  // Eyeball colour (iris desaturated, so that τ_iris gives its hue) with the
  // iris weight (1 in the iris, 0 on the sclera) in the fourth channel.
  const RgbaTexture& eyeball_texture() const { return eyeball_texture_; }
  // Triangles per part, counter-clockwise seen from outside (the right eye's
  // are re-wound after mirroring).
  const std::vector<Eigen::Vector3i>& triangles(int part) const { return triangles_[part]; }
  int num_vertices(int part) const { return IsEyeball(part) ? eyeball_.num_vertices() : subdivision_.num_vertices(); }
  // All parts in one list, for the renderer: part p's vertices start at
  // vertex_offset(p) and its triangles at triangle_offset(p); the triangles of
  // all_triangles() index the concatenated vertices.
  int vertex_offset(int part) const { return vertex_offsets_[part]; }
  int triangle_offset(int part) const { return triangle_offsets_[part]; }
  int total_vertices() const { return vertex_offsets_[kNumParts]; }
  const std::vector<Eigen::Vector3i>& all_triangles() const { return all_triangles_; }
  const Eigen::Matrix2Xd& skin_uvs() const { return skin_uvs_; }
  // The subdivided skin vertices on the rim of the eye opening: the eyeball
  // can only be seen within their outline.
  const std::vector<int>& opening_rim() const { return opening_rim_; }
  // The eyeball's angular coordinates in single precision, for shading.
  const Eigen::Matrix2Xf& eyeball_angles() const { return eyeball_angles_; }

  // The eye's gaze direction in the head frame (x: subject's left, y: down,
  // z: into the head) for pitch, yaw (degrees) and the vergence share of this eye.
  static Eigen::Vector3d GazeInHead(double pitch_deg, double yaw_deg);
  // The inverse: pitch and yaw (degrees) of a direction in the head frame.
  static Eigen::Vector2d PitchYawInHead(const Eigen::Vector3d& direction);
  static Eigen::Matrix3d GazeRotation(double pitch_deg, double yaw_deg);
  // A gaze direction's pitch and yaw (degrees) relative to the camera, as
  // relative to a head turned by `head_yaw_deg` (Parameters::rotation_deg().y());
  // with -head_yaw_deg, the other way.
  static Eigen::Vector2d CameraGazeInHead(double pitch_deg, double yaw_deg, double head_yaw_deg);
  // Yaw of one eye: vergence turns each eye toward the nose by half its angle.
  static double EyeYaw(const Parameters& phi, int eye);
  // The eyeball centre in the head frame.
  static Eigen::Vector3d EyeCentreInHead(const Parameters& phi, int eye);
  // A point in camera coordinates (mm) in Φ's head frame.
  static Eigen::Vector3d PointInHead(const Parameters& phi, const Eigen::Vector3d& point);
  // Gaze pitch, yaw and vergence (degrees) that make both eyes of Φ's head
  // look at `point` (camera coordinates, mm).
  static Eigen::Vector3d FixationAngles(const Parameters& phi, const Eigen::Vector3d& point);
  // Model frame of the left eye -> head frame (x, y, z) -> (x, -z, y); the
  // right eye mirrors x first.
  static Eigen::Matrix3d ModelToHead(int eye);

 private:
  // One eye's facial region: the lids rigged for Φ's lids and gaze (left in
  // work.rigged, in the model frame), then placed and subdivided.
  void PoseSkin(const Parameters& phi, const Eigen::Matrix3d& gaze_model, const PosedEye& eye, PosedPart& skin,
                PoseWorkspace& work) const;
  // One eyeball placed as `eye` says, its texture coordinates refracted for the view.
  void PoseEyeball(double iris_size, const PosedEye& eye, PosedPart& ball, PoseWorkspace& work) const;
  // The lid margins of the rigged region as cubics in the eyeball's angles.
  static void FitLidMargins(const Eigen::Matrix3d& gaze_model, const Eigen::Matrix3Xd& rigged, PosedEye& eye);

  ShapeModel shape_;
  Subdivision subdivision_;
  EyeballModel eyeball_;
  EyelidRig rig_;
  SkinTextureModel skin_texture_;
  RgbaTexture eyeball_texture_;
  std::vector<RgbaTexture> texture_modes_;
  Eigen::Matrix2Xd skin_uvs_;
  std::array<std::vector<Eigen::Vector3i>, kNumParts> triangles_;
  std::vector<Eigen::Vector3i> base_triangles_;  // the coarse facial mesh, for its normals
  std::vector<int> opening_rim_;
  Eigen::Matrix2Xf eyeball_angles_;
  Eigen::Matrix3Xf eyeball_positions_, eyeball_normals_;  // the eyeball's, in floats for posing
  std::array<int, kNumParts + 1> vertex_offsets_{};
  std::array<int, kNumParts + 1> triangle_offsets_{};
  std::vector<Eigen::Vector3i> all_triangles_;
};

}  // namespace gazedirector
