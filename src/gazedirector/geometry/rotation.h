#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace gazedirector {

// Rotation from Euler angles (radians) as OpenFace reports head pose:
// R = Rx(x) * Ry(y) * Rz(z).
Eigen::Matrix3d RotationFromEulerXYZ(const Eigen::Vector3d& angles);
Eigen::Vector3d EulerXYZFromRotation(const Eigen::Matrix3d& rotation);

// Axis-angle (Rodrigues) vector <-> matrix.
Eigen::Matrix3d RotationFromAxisAngle(const Eigen::Vector3d& axis_angle);
Eigen::Vector3d AxisAngleFromRotation(const Eigen::Matrix3d& rotation);

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double DegToRad(double degrees) { return degrees * kPi / 180.0; }
inline constexpr double RadToDeg(double radians) { return radians * 180.0 / kPi; }
// True for an angle of at most a quarter turn either way; false for NaN. Gaze
// and lid angles beyond it point behind the head or wrap around.
inline bool WithinQuarterTurn(double degrees) { return degrees >= -90.0 && degrees <= 90.0; }

}  // namespace gazedirector
