#pragma once

#include <array>
#include <filesystem>

#include <Eigen/Core>

#include "gazedirector/face/face.h"

namespace gazedirector {

// The mean 3D positions of the 68 landmarks, converted to the head frame
// (x toward the subject's left, y down, z into the head, millimetres).
using MeanFace = std::array<Eigen::Vector3d, kNumLandmarks>;

// Reads assets/face/landmarks68_mean3d.json (y up, z toward the viewer).
MeanFace LoadMeanFace(const std::filesystem::path& path);

}  // namespace gazedirector
