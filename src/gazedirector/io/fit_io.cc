#include "gazedirector/io/fit_io.h"

#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "gazedirector/face/face_io.h"
#include "gazedirector/geometry/rotation.h"
#include "gazedirector/io/json_format.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace {

nlohmann::json Vector(const Eigen::Vector3d& v, int digits) {
  return {RoundTo(v.x(), digits), RoundTo(v.y(), digits), RoundTo(v.z(), digits)};
}

nlohmann::json EyeJson(const EyeGaze& eye) {
  return {{"centre_mm", Vector(eye.centre, 2)},
          {"gaze", Vector(eye.gaze, 5)},
          {"pitch_deg", RoundTo(eye.pitch_deg, 2)},
          {"yaw_deg", RoundTo(eye.yaw_deg, 2)}};
}

// The mean gaze of the fitted eyes.
Eigen::Vector3d MeanGaze(const std::array<EyeGaze, 2>& gazes, const std::array<bool, 2>& eyes) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int eye = 0; eye < 2; ++eye) {
    if (eyes[eye]) sum += gazes[eye].gaze;
  }
  return sum.normalized();
}

}  // namespace

nlohmann::json ToJson(const FaceFit& fit) {
  nlohmann::json record = fit.has_face ? ToJson(fit.face) : nlohmann::json{{"face_id", fit.face.id}};
  const EnergyTerms& terms = fit.fit.terms;
  record["fit"] = {{"energy", RoundTo(terms.total(), 6)},
                   {"image_energy", RoundTo(terms.image, 6)},
                   {"landmark_energy", RoundTo(terms.landmarks, 6)},
                   {"landmark_error", std::isfinite(fit.fit.landmark_error) ? nlohmann::json(RoundTo(fit.fit.landmark_error, 4))
                                                                           : nlohmann::json(nullptr)},
                   {"model_pixels", terms.foreground},
                   {"iterations", fit.fit.iterations},
                   {"warm_start", fit.warm},
                   {"eyes_closed", fit.eyes_closed},
                   {"good", fit.fit.good},
                   {"note", fit.fit.note}};
  const std::array<EyeGaze, 2> gazes = EyeGazes(fit.fit.phi);
  record["eyes"] = nlohmann::json::object();
  if (fit.eyes[kLeftEye]) record["eyes"]["left"] = EyeJson(gazes[kLeftEye]);
  if (fit.eyes[kRightEye]) record["eyes"]["right"] = EyeJson(gazes[kRightEye]);
  const Eigen::Vector2d angles = GazeAngles(MeanGaze(gazes, fit.eyes));
  record["gaze_angle_rad"] = {RoundTo(angles.x(), 5), RoundTo(angles.y(), 5)};
  record["parameters"] = fit.fit.phi.ToJson();
  return record;
}

nlohmann::json FrameRecord(long frame, double timestamp_s, const std::vector<FaceFit>& fits, const Camera* camera) {
  nlohmann::json record = {{"frame", frame}, {"timestamp", RoundTo(timestamp_s, 4)}};
  if (camera != nullptr) record["camera"] = ToJson(*camera);
  record["faces"] = nlohmann::json::array();
  for (const FaceFit& fit : fits) record["faces"].push_back(ToJson(fit));
  return record;
}

std::vector<std::string> FitCsvColumns() {
  std::vector<std::string> columns = {"frame", "face_id", "timestamp", "confidence", "success"};
  for (const char* eye : {"gaze_0", "gaze_1"}) {
    for (const char* axis : {"x", "y", "z"}) columns.push_back(fmt::format("{}_{}", eye, axis));
  }
  for (const char* eye : {"eye_0", "eye_1"}) {
    for (const char* axis : {"X", "Y", "Z"}) columns.push_back(fmt::format("{}_centre_{}", eye, axis));
  }
  for (const char* name : {"gaze_angle_x", "gaze_angle_y", "pose_Tx", "pose_Ty", "pose_Tz", "pose_Rx", "pose_Ry",
                           "pose_Rz", "eyelid_pitch", "eyelid_closure", "AU45_c", "energy", "fit_good"}) {
    columns.push_back(name);
  }
  return columns;
}

std::vector<std::string> FitCsvRow(long frame, double timestamp_s, const FaceFit* fit) {
  std::vector<std::string> row = {std::to_string(frame), fit ? std::to_string(fit->face.id) : "-1",
                                  fmt::format("{:.3f}", timestamp_s),
                                  fmt::format("{:.3f}", fit ? fit->face.confidence : 0.0), fit ? "1" : "0"};
  if (fit == nullptr) {
    row.resize(FitCsvColumns().size(), "0");
    return row;
  }
  const Parameters& phi = fit->fit.phi;
  const std::array<EyeGaze, 2> gazes = EyeGazes(phi);
  // OpenFace's eye 0 is the one on the image left: the subject's right.
  const int order[2] = {kRightEye, kLeftEye};
  for (int eye : order) {
    for (int i = 0; i < 3; ++i) row.push_back(fmt::format("{:.5f}", gazes[eye].gaze[i]));
  }
  for (int eye : order) {
    for (int i = 0; i < 3; ++i) row.push_back(fmt::format("{:.2f}", gazes[eye].centre[i]));
  }
  const Eigen::Vector2d angles = GazeAngles(MeanGaze(gazes, fit->eyes));
  row.push_back(fmt::format("{:.5f}", angles.x()));
  row.push_back(fmt::format("{:.5f}", angles.y()));
  const Eigen::Vector3d euler = EulerXYZFromRotation(fit->face.pose.rotation);
  for (int i = 0; i < 3; ++i) row.push_back(fmt::format("{:.1f}", fit->face.pose.translation[i]));
  for (int i = 0; i < 3; ++i) row.push_back(fmt::format("{:.4f}", euler[i]));
  row.push_back(fmt::format("{:.2f}", phi.eyelid_pitch()));
  row.push_back(fmt::format("{:.2f}", phi.eyelid_closure()));
  row.push_back(fit->eyes_closed ? "1" : "0");  // OpenFace's blink action unit
  row.push_back(fmt::format("{:.6f}", fit->fit.terms.total()));
  row.push_back(fit->fit.good ? "1" : "0");
  return row;
}

StoredFit StoredFit::Of(const FaceFit& fit) {
  return {fit.face.id, fit.fit.phi, fit.fit.good, fit.fit.note, fit.eyes, fit.eyes_closed};
}

FitsFile ReadFits(const std::filesystem::path& path) {
  std::ifstream stream(path);
  if (!stream) Fail(ExitCode::kBadInput, "{}: cannot read the fits file", path.string());
  FitsFile file;
  // A single-image fits file may be one pretty-printed document.
  std::string text((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
  std::vector<nlohmann::json> records;
  try {
    const nlohmann::json whole = nlohmann::json::parse(text);
    records.push_back(whole);
  } catch (const nlohmann::json::exception&) {
    std::istringstream lines(text);
    std::string line;
    long line_number = 0;
    while (std::getline(lines, line)) {
      ++line_number;
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      try {
        records.push_back(nlohmann::json::parse(line));
      } catch (const nlohmann::json::exception& e) {
        Fail(ExitCode::kBadInput, "{}:{}: not a JSON line ({})", path.string(), line_number, JsonErrorText(e));
      }
    }
  }
  long index = 0;
  for (const nlohmann::json& record : records) {
    ++index;
    try {
      if (record.contains("camera")) file.camera = CameraFromJson(record.at("camera"));
      StoredFrame frame;
      frame.frame = record.value("frame", 0L);
      frame.timestamp_s = record.value("timestamp", 0.0);
      for (const nlohmann::json& face : record.at("faces")) {
        StoredFit fit;
        fit.face_id = face.value("face_id", 0);
        fit.phi = Parameters::FromJson(face.at("parameters"));
        if (face.contains("fit")) {
          fit.good = face["fit"].value("good", false);
          fit.note = face["fit"].value("note", std::string());
          fit.eyes_closed = face["fit"].value("eyes_closed", false);
        }
        if (face.contains("eyes") && !face["eyes"].empty()) {
          fit.eyes = {face["eyes"].contains("left"), face["eyes"].contains("right")};
        }
        frame.faces.push_back(std::move(fit));
      }
      file.frames[frame.frame] = std::move(frame);
    } catch (const nlohmann::json::exception& e) {
      Fail(ExitCode::kBadInput, "{}: record {}: {}", path.string(), index, JsonErrorText(e));
    } catch (const Error& e) {
      Fail(e.code(), "{}: record {}: {}", path.string(), index, e.what());
    }
  }
  if (file.frames.empty()) Fail(ExitCode::kBadInput, "{}: no fits in the file", path.string());
  return file;
}

}  // namespace gazedirector
