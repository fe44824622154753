#pragma once

#include <array>
#include <string>
#include <string_view>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace gazedirector {

// The named blocks of the model parameters Φ, as in the paper: shape β,
// texture τ, pose θ and illumination ι. Angles are in degrees, lengths in
// millimetres, PCA coefficients in standard deviations and colours linear RGB
// in [0, 1] (light intensities may exceed 1).
enum class Block : int {
  kShape,           // β_face: 16 shape PCA coefficients, shared by both eyes
  kIrisSize,        // β_iris: limbus radius relative to the model's 5.87 mm
  kTexture,         // τ_face: 8 texture PCA coefficients
  kIrisColour,      // τ_iris: RGB multiplier of the iris
  kScleraTint,      // τ_tint: RGB multiplier of the white of the eye
  kRotation,        // θ_R: eye-region frame -> camera, Euler XYZ (R = Rx Ry Rz)
  kTranslation,     // θ_T: the midpoint between the eyeball centres, camera frame
  kInterocular,     // θ_iod: distance between the eyeball centres
  kGaze,            // θ_p, θ_y, θ_v: gaze pitch (up +), yaw (toward the subject's left +), vergence (converging +)
  kEyelid,          // θ_lid: eyelid pitch (up +)
  kEyelidClosure,   // θ_close: upper lid lowered (and lower lid raised) apart from the gaze, degrees; squints and blinks
  kAmbient,         // ι_amb: ambient light RGB
  kLightColour,     // ι_dir: directional light RGB
  kLightDirection,  // ι_R: direction toward the light, pitch (up +) and yaw (image right +), camera frame
  kPupilSize,       // β_pupil: pupil radius relative to the iris's (the eyeball texture's pupil: 0.49)
};

struct BlockLayout {
  Block block;
  std::string_view name;  // JSON key, with its unit
  int offset;
  int size;
};

inline constexpr int kNumShapeModes = 16;
inline constexpr int kNumTextureModes = 8;

inline constexpr std::array<BlockLayout, 15> kBlockLayout = {{
    {Block::kShape, "shape_sd", 0, kNumShapeModes},
    {Block::kIrisSize, "iris_size", 16, 1},
    {Block::kTexture, "texture_sd", 17, kNumTextureModes},
    {Block::kIrisColour, "iris_rgb", 25, 3},
    {Block::kScleraTint, "sclera_rgb", 28, 3},
    {Block::kRotation, "rotation_deg", 31, 3},
    {Block::kTranslation, "translation_mm", 34, 3},
    {Block::kInterocular, "interocular_mm", 37, 1},
    {Block::kGaze, "gaze_pitch_yaw_vergence_deg", 38, 3},
    {Block::kEyelid, "eyelid_pitch_deg", 41, 1},
    {Block::kEyelidClosure, "eyelid_closure_deg", 42, 1},
    {Block::kAmbient, "ambient_rgb", 43, 3},
    {Block::kLightColour, "light_rgb", 46, 3},
    {Block::kLightDirection, "light_pitch_yaw_deg", 49, 2},
    {Block::kPupilSize, "pupil_size", 51, 1},
}};

inline constexpr int kNumParameters = 52;

constexpr const BlockLayout& LayoutOf(Block block) { return kBlockLayout[static_cast<int>(block)]; }

// A mask over the parameters: which are optimised (true) and which held.
using ParameterMask = std::array<bool, kNumParameters>;
ParameterMask MaskOf(std::initializer_list<Block> blocks);
// Marks the blocks' parameters held (false) in a mask of free parameters.
void Hold(ParameterMask& free, std::initializer_list<Block> blocks);
ParameterMask AllParameters();

class Parameters {
 public:
  using Vector = Eigen::Matrix<double, kNumParameters, 1>;

  // The mean face and texture, average iris size and interocular distance,
  // gaze at the camera through an unrotated head, and a basic light from the
  // camera. Translation is zero until initialised.
  Parameters();

  Vector values;

  template <Block B>
  auto block() {
    return values.segment<LayoutOf(B).size>(LayoutOf(B).offset);
  }
  template <Block B>
  auto block() const {
    return values.segment<LayoutOf(B).size>(LayoutOf(B).offset);
  }
  double& operator[](int index) { return values[index]; }
  double operator[](int index) const { return values[index]; }

  auto shape() { return block<Block::kShape>(); }
  auto shape() const { return block<Block::kShape>(); }
  auto texture() { return block<Block::kTexture>(); }
  auto texture() const { return block<Block::kTexture>(); }
  double& iris_size() { return values[LayoutOf(Block::kIrisSize).offset]; }
  double iris_size() const { return values[LayoutOf(Block::kIrisSize).offset]; }
  double& pupil_size() { return values[LayoutOf(Block::kPupilSize).offset]; }
  double pupil_size() const { return values[LayoutOf(Block::kPupilSize).offset]; }
  Eigen::Vector3d iris_colour() const { return block<Block::kIrisColour>(); }
  Eigen::Vector3d sclera_tint() const { return block<Block::kScleraTint>(); }
  Eigen::Vector3d rotation_deg() const { return block<Block::kRotation>(); }
  Eigen::Vector3d translation() const { return block<Block::kTranslation>(); }
  double& interocular() { return values[LayoutOf(Block::kInterocular).offset]; }
  double interocular() const { return values[LayoutOf(Block::kInterocular).offset]; }
  double& gaze_pitch() { return values[LayoutOf(Block::kGaze).offset]; }
  double gaze_pitch() const { return values[LayoutOf(Block::kGaze).offset]; }
  double& gaze_yaw() { return values[LayoutOf(Block::kGaze).offset + 1]; }
  double gaze_yaw() const { return values[LayoutOf(Block::kGaze).offset + 1]; }
  double& vergence() { return values[LayoutOf(Block::kGaze).offset + 2]; }
  double vergence() const { return values[LayoutOf(Block::kGaze).offset + 2]; }
  double& eyelid_pitch() { return values[LayoutOf(Block::kEyelid).offset]; }
  double eyelid_pitch() const { return values[LayoutOf(Block::kEyelid).offset]; }
  double& eyelid_closure() { return values[LayoutOf(Block::kEyelidClosure).offset]; }
  double eyelid_closure() const { return values[LayoutOf(Block::kEyelidClosure).offset]; }
  Eigen::Vector3d ambient() const { return block<Block::kAmbient>(); }
  Eigen::Vector3d light_colour() const { return block<Block::kLightColour>(); }
  Eigen::Vector2d light_direction_deg() const { return block<Block::kLightDirection>(); }

  void set_rotation(const Eigen::Matrix3d& rotation);
  Eigen::Matrix3d rotation() const;

  // The unit vector toward the light in camera coordinates.
  Eigen::Vector3d LightDirection() const;
  // Its derivatives by the light's pitch and yaw (the columns), per degree.
  Eigen::Matrix<double, 3, 2> LightDirectionJacobian() const;

  nlohmann::json ToJson() const;
  // Missing blocks keep their defaults; wrong sizes fail with ExitCode::kBadInput.
  static Parameters FromJson(const nlohmann::json& json);

  // "shape_sd[3]", "gaze_yaw", ... for logs and plots.
  static std::string NameOf(int index);
  static Block BlockOf(int index);
};

}  // namespace gazedirector
