#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gazedirector/fit/face_fit.h"
#include "gazedirector/geometry/camera.h"

namespace gazedirector {

// The record of one fitted face: the face (id, landmarks, head pose), the
// fit's energy and quality, each eye's gaze in camera coordinates, OpenFace's
// gaze angles and Φ* itself, which `redirect --fits` reads back.
nlohmann::json ToJson(const FaceFit& fit);

// One line of a fits file (JSON lines): a frame and its faces.
nlohmann::json FrameRecord(long frame, double timestamp_s, const std::vector<FaceFit>& fits,
                           const Camera* camera = nullptr);

// CSV with OpenFace's column names where they overlap: gaze_0 is the eye on
// the image left (the subject's right), gaze_1 the other.
std::vector<std::string> FitCsvColumns();
std::vector<std::string> FitCsvRow(long frame, double timestamp_s, const FaceFit* fit);

// A face's fit as read back from a fits file.
struct StoredFit {
  int face_id = 0;
  Parameters phi;
  bool good = false;
  std::string note;
  std::array<bool, 2> eyes = {true, true};
  bool eyes_closed = false;  // the tracker saw a blink

  // What a fits file would keep of a fit made now.
  static StoredFit Of(const FaceFit& fit);
};

struct StoredFrame {
  long frame = 0;
  double timestamp_s = 0;
  std::vector<StoredFit> faces;
};

struct FitsFile {
  std::optional<Camera> camera;         // the camera the fits were made with
  std::map<long, StoredFrame> frames;   // by frame index
};

// Reads a fits file written by `track` (and perhaps edited by hand). Fails
// with ExitCode::kBadInput, naming the line, when it cannot be understood.
FitsFile ReadFits(const std::filesystem::path& path);

}  // namespace gazedirector
