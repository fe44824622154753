#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gazedirector/fit/fitter.h"

namespace gazedirector {

// One crop of the Columbia Gaze data set, named SSSS_2m_{P}P_{V}V_{H}H_{E}.jpg.
struct ColumbiaCrop {
  std::filesystem::path path;
  std::string subject;
  int head_pose = 0;  // P: the camera's horizontal position around the head, degrees
  int vertical = 0;   // V: gaze target elevation, degrees (up +)
  int horizontal = 0;  // H: gaze target azimuth, degrees (toward image right at P = 0)
  char eye = 'L';     // L: the image-left eye (the subject's right); R: the subject's left
  int ModelEye() const;
  // The photo both eyes' crops come from: the file name without _L/_R.
  std::string Photo() const;
};

// Parses a crop's file name; false when it is not one.
bool ParseColumbiaName(const std::filesystem::path& path, ColumbiaCrop& crop);
// Every crop in `dir`, sorted by name.
std::vector<ColumbiaCrop> ListColumbia(const std::filesystem::path& dir);

// The fit of one crop, compared with its label. Gaze relative to the head:
// the model's eyeball pitch and yaw in its eye-region frame, in degrees.
struct ColumbiaFit {
  ColumbiaCrop crop;
  double pitch = 0, yaw = 0;
  double pitch_error = 0, yaw_error = 0;  // absolute, degrees
  double head_pitch = 0, head_yaw = 0;    // the eye region's fitted rotation, degrees
  // The gaze in the camera's frame, relative to the line from the eye to
  // the camera (degrees; up +, toward image right +).
  double camera_pitch = 0, camera_yaw = 0;
  double energy = 0;  // the fit's final E
  double seconds = 0;
  // Per Gauss-Newton iterate (0: the start): photometric energy and gaze
  // error (degrees, the angle between estimated and labelled directions).
  std::vector<double> energy_by_iteration;
  std::vector<double> gaze_error_by_iteration;
};

// The gaze of one photo's face. Where both eyes' crops are there it is the
// mean of the two eyes' fits, as in the paper's model, whose two eyeballs
// share one pitch and yaw: the eyes look at the same target, and errors that
// mirror between them (where each eyeball sits behind its lids) cancel.
struct ColumbiaPhoto {
  ColumbiaCrop crop;  // the first eye's crop: the photo's labels
  int eyes = 0;       // 1 or 2
  double pitch = 0, yaw = 0;
  double pitch_error = 0, yaw_error = 0;  // absolute, degrees
};

// One entry per photo, in the order of the fits.
std::vector<ColumbiaPhoto> CombineEyes(const std::vector<ColumbiaFit>& fits);

// Fits every crop with `threads` fitters working side by side; `progress`
// is called after each crop.
// With `known_head_pose`, the eye region's yaw is the crop's P and held
// there (the camera's position around the head, from the file name), as when
// a face tracker supplies the head pose; otherwise it is estimated.
std::vector<ColumbiaFit> FitColumbia(const std::vector<ColumbiaCrop>& crops, std::shared_ptr<const EyeRegionModel> model,
                                     const FitOptions& options, int threads, bool known_head_pose,
                                     const std::function<void(int done)>& progress = nullptr);

// The angle between two gaze directions given as pitch and yaw (degrees).
double GazeAngleBetween(double pitch_a, double yaw_a, double pitch_b, double yaw_b);

}  // namespace gazedirector
