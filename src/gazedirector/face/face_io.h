#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gazedirector/face/face.h"
#include "gazedirector/geometry/camera.h"

namespace gazedirector {

nlohmann::json ToJson(const Face& face);
nlohmann::json ToJson(const Camera& camera);
nlohmann::json ToJson(const HeadPose& pose);
Camera CameraFromJson(const nlohmann::json& json);

// CSV columns named as OpenFace names them: frame, face_id, timestamp,
// confidence, success, pose_Tx..pose_Rz, x_0..x_67, y_0..y_67.
std::vector<std::string> FaceCsvColumns();
// One row; a null face gives a "no face" row (face_id -1, success 0).
std::vector<std::string> FaceCsvRow(long frame, double timestamp_s, const Face* face);

}  // namespace gazedirector
