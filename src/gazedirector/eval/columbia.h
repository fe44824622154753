#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gazedirector/fit/appearance_gaze.h"
#include "gazedirector/fit/fitter.h"

namespace gazedirector {

// The frame a gaze direction is given in: the head's (the eyeball's pitch and
// yaw in the eye region, the model's convention) or the camera's (relative to
// the line from the eye to the camera: up +, toward image right +).
enum class GazeFrame { kHead, kCamera };

// One crop of the Columbia Gaze data set, named SSSS_2m_{P}P_{V}V_{H}H_{E}.jpg.
// Its labels V and H are relative to the camera: 0V 0H looks into the lens at
// every head pose (the data set's "gaze locking" photos), so at P = +-30 a
// 0V 0H eye is turned 30 degrees in the head.
struct ColumbiaCrop {
  std::filesystem::path path;
  std::string subject;
  int head_pose = 0;  // P: the camera's horizontal position around the head, degrees
  int vertical = 0;   // V: gaze target elevation, degrees (up +)
  int horizontal = 0;  // H: gaze target azimuth, degrees (toward image right at P = 0)
  char eye = 'L';     // L: the image-left eye (the subject's right); R: the subject's left
  int ModelEye() const;
  // The head's yaw in the camera's frame (the model's rotation_deg().y()):
  // the camera sat P degrees around the head, so the head is turned by -P
  // (fits held at -P explain the +-30 crops better than at +P in 369 of 499).
  double HeadYaw() const;
  // The labelled gaze (pitch, yaw in degrees) in `frame`; in the head's frame
  // it is the label's direction turned by the head's yaw.
  Eigen::Vector2d Label(GazeFrame frame) const;
  // The photo both eyes' crops come from: the file name without _L/_R.
  std::string Photo() const;
};

// Parses a crop's file name; false when it is not one.
bool ParseColumbiaName(const std::filesystem::path& path, ColumbiaCrop& crop);
// `dir`, or ../shared/data/columbia-eyes when it is empty.
std::filesystem::path ColumbiaDirOrDefault(const std::string& dir);
// Every crop in `dir` and its subfolders (not hidden ones: a subject per
// folder, say), sorted by path. Other files, crops that cannot be decoded and
// a name met a second time are skipped with a warning (and listed in
// `skipped` when given), so that one bad file does not stop a long run.
std::vector<ColumbiaCrop> ListColumbia(const std::filesystem::path& dir,
                                       std::vector<std::filesystem::path>* skipped = nullptr);

// A gaze direction in one frame and its absolute error against the label, degrees.
struct GazeReading {
  double pitch = 0, yaw = 0;
  double pitch_error = 0, yaw_error = 0;
};

// An estimate compared with its label in both frames.
struct GazeReadings {
  GazeReading in_head, in_camera;
  const GazeReading& Reading(GazeFrame frame) const { return frame == GazeFrame::kHead ? in_head : in_camera; }
};

// The fit of one crop.
struct ColumbiaFit : GazeReadings {
  ColumbiaCrop crop;
  double head_pitch = 0, head_yaw = 0;  // the eye region's fitted rotation, degrees
  double energy = 0;  // the fit's final E
  double seconds = 0;
  // The crop's appearance reading (the prior the fit was pulled toward), NaN without one.
  AppearanceReading appearance;
  // Per Gauss-Newton iterate (0: the start): photometric energy and gaze
  // error in the head's frame (degrees, the angle between estimated and
  // labelled directions).
  std::vector<double> energy_by_iteration;
  std::vector<double> gaze_error_by_iteration;
};

// The gaze of one photo's face. Where both eyes' crops are there it is the
// mean of the two eyes' fits, as in the paper's model, whose two eyeballs
// share one pitch and yaw: the eyes look at the same target, and errors that
// mirror between them (where each eyeball sits behind its lids) cancel.
struct ColumbiaPhoto : GazeReadings {
  ColumbiaCrop crop;  // the first eye's crop: the photo's labels
  int eyes = 0;       // 1 or 2
};

// One entry per photo, in the order of the fits.
std::vector<ColumbiaPhoto> CombineEyes(const std::vector<ColumbiaFit>& fits);

// How far the mean errors could move on other people like these: one
// person's photos share that person's bias, so the photos are resampled by
// subject. `draws` times the subjects are drawn with replacement (as many as
// there are) and the mean yaw and pitch errors of all their photos taken; the
// result is the 5th and 95th percentiles of those means.
struct SubjectResampling {
  int subjects = 0, draws = 0;
  double yaw_low = 0, yaw_high = 0;
  double pitch_low = 0, pitch_high = 0;
};
SubjectResampling ResampleSubjects(const std::vector<ColumbiaPhoto>& photos, GazeFrame frame, int draws = 2000,
                                   unsigned seed = 1);

// How the head's yaw read from a photo's crops (the reading its fits were
// given) errs at one head pose, and how much of that each person carries into
// all their photos: the spread of the subjects' mean readings against how far
// a photo's reading strays from its subject's mean.
struct HeadYawReadings {
  int head_pose = 0, photos = 0, subjects = 0;
  double mean_reading = 0;                  // degrees
  double mean_error = 0, mean_abs_error = 0;  // the reading less the head's yaw, -P
  double subject_spread = 0;  // standard deviation over the subjects of a subject's mean reading
  double within_subject = 0;  // a photo's mean distance from its subject's mean reading
};

// One entry per head pose, in order, over the photos whose fits had a head
// reading: fits with the head's yaw read (not given, where a fit's reading
// carries the given yaw) and the appearance prior on.
std::vector<HeadYawReadings> SummariseHeadYawReadings(const std::vector<ColumbiaFit>& fits);

// Every crop added to a trainer, by subject, with its gaze relative to the
// head and its head yaw as labels.
void AddColumbiaCrops(const std::vector<ColumbiaCrop>& crops, AppearanceGazeTrainer& trainer);

// Appearance gaze models for an honest evaluation: for each of `subjects`,
// the trainer's model without that subject's crops, so that no crop is read
// by a model that has seen its person. Subjects the trainer has no crops of
// share one model of all its crops, solved once.
std::map<std::string, AppearanceGaze> LeaveSubjectOut(const AppearanceGazeTrainer& trainer,
                                                      const std::vector<std::string>& subjects);

// The head's yaw each photo's crops read (Photo() -> degrees), the mean of
// its eyes' readings by their subject's model: the turn of the head shows
// better in two eyes than in one.
std::map<std::string, double> ReadHeadYawByPhoto(const std::vector<ColumbiaCrop>& crops,
                                                 const std::map<std::string, AppearanceGaze>& models);

// Fits every crop with `threads` fitters working side by side; `progress`
// is called after each crop.
// With `known_head_pose`, the eye region's yaw is the crop's HeadYaw() and
// held there (from P in the file name), as when a face tracker supplies the
// head pose; otherwise it is estimated. With `appearance` (models by
// subject), each crop's gaze is pulled toward its subject's model's reading
// (EnergyWeights::appearance_pitch and appearance_yaw) for the known head
// yaw or, without it, for its photo's reading (ReadHeadYawByPhoto), where the
// fit then starts its head yaw; a subject without a model fails.
std::vector<ColumbiaFit> FitColumbia(const std::vector<ColumbiaCrop>& crops, std::shared_ptr<const EyeRegionModel> model,
                                     const FitOptions& options, int threads, bool known_head_pose,
                                     const std::function<void(int done)>& progress = nullptr,
                                     const std::map<std::string, AppearanceGaze>* appearance = nullptr);

// The angle between two gaze directions given as pitch and yaw (degrees).
double GazeAngleBetween(double pitch_a, double yaw_a, double pitch_b, double yaw_b);

}  // namespace gazedirector
