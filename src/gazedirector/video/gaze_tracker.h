#pragma once

#include <map>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "gazedirector/face/eye_opening.h"
#include "gazedirector/face/face_tracker.h"
#include "gazedirector/fit/face_fit.h"
#include "gazedirector/fit/fitter.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/render/renderer.h"
#include "gazedirector/util/thread_pool.h"

namespace gazedirector {

// The fitter's options for a frame that starts from the previous frame's fit:
// few iterations on the finest level only, jumps of gaze tried first.
FitOptions WarmFitOptions();

struct GazeTrackerOptions {
  HeadPoseMethod head_pose = HeadPoseMethod::kPerspectiveNPoint;  // the faces' head pose, which the fits start from
  FitOptions fresh;                   // for a face seen for the first time (or refitted)
  FitOptions warm = WarmFitOptions();  // for a face followed from the previous frame
  // After this many fits of a face its shape, texture (skin, iris colour,
  // sclera tint), iris size and interocular distance are held (the paper's
  // parameter masking): they do not change from frame to frame, and fewer
  // parameters fit faster. A frame whose fit still runs into the lids' bound
  // (or a pitch beyond it) after a refit (an expression the settled shape cannot
  // follow: eyes opened wide) is fitted with a shape and texture of its own,
  // and so are the next frames until the settled ones explain them as well.
  int settle_frames = 3;
  // A warm fit whose energy exceeds this multiple of the face's typical
  // energy is redone from the landmarks (the fit lost the eyes).
  double refit_ratio = 1.8;
  // Blinks: when the less open eye's landmark opening (eye aspect ratio)
  // falls below this fraction of the face's usual one, the eyeballs are hidden
  // and their gaze cannot be seen: it is held at the last open frame's while
  // the lids are fitted, starting `closed_lid_deg` of closure short of fully open
  // per unit of lost opening. Without this the lids closed by looking far
  // down and aside, and the gaze swung to its limits for the blink's frames.
  // Eyes that stay that narrow for longer than a blink are looking down (the
  // lids follow the gaze) or squinting: their gaze is fitted again.
  double closed_eye_fraction = 0.6;
  double closed_lid_deg = 42;
  double max_blink_s = 0.5;
  // Converging eyes (a face looking at something near: a phone held close, a
  // screen): the vergence prior holds the eyes' axes parallel, which most
  // faces' are, so where the photo's irises converge it fits one iris beside
  // its eye. A fresh fit whose iris sits more than this many iris radii from
  // the photo's (IrisMisalignment) is fitted again with the vergence free, and
  // the refit kept where it converges, its irises sit within this distance and
  // closer, at no more image energy; the face's warm fits then keep the
  // vergence free. 0: never.
  double free_vergence_iris_offset = 0.7;
  // The warm options with the settled parameters held.
  FitOptions SettledWarm() const;
};

// Finds faces and fits the eye-region model to each, in stills and videos.
// In a video every face keeps its fit from frame to frame: the next frame
// starts from it, with the settled parameters held.
class GazeTracker {
 public:
  GazeTracker(std::shared_ptr<const EyeRegionModel> model, std::shared_ptr<const LandmarkDetector> landmarks,
              MeanFace mean_face, GazeTrackerOptions options = {},
              std::shared_ptr<ThreadPool> pool = nullptr, bool largest_only = false);

  std::vector<FaceFit> ProcessImage(const cv::Mat& image, const Camera& camera);
  // ProcessImage's fits of faces found by a FaceTracker with FaceOptions.
  std::vector<FaceFit> FitImageFaces(const cv::Mat& image, const Camera& camera, const std::vector<Face>& faces);
  // The options of the tracker's own face tracker.
  static FaceTrackerOptions FaceOptions(bool largest_only, HeadPoseMethod head_pose = HeadPoseMethod::kPerspectiveNPoint);
  // TrackFaces, then FitFaces.
  std::vector<FaceFit> ProcessFrame(const cv::Mat& frame, double timestamp_s, const Camera& camera);
  // A video frame's two stages. They touch separate state (the face tracker;
  // the faces' fits), so one thread may track a frame's faces while another
  // fits the previous frame's (TrackedFrameReader), frames in order in each.
  std::vector<Face> TrackFaces(const cv::Mat& frame, double timestamp_s, const Camera& camera);
  std::vector<FaceFit> FitFaces(const cv::Mat& frame, double timestamp_s, const Camera& camera,
                                const std::vector<Face>& faces);
  void Reset();

 private:
  struct History {
    Parameters phi;
    Parameters settled;  // the fit whose shape and texture were held from settle_frames on
    int fits = 0;
    double typical_energy = 0;  // running average of good fits' energies
    EyeOpeningTracker opening;
    double narrow_since_s = -1;  // when the eyes became narrower than a blink's threshold; -1 while open
    bool free_vergence = false;  // the face's eyes converge (free_vergence_iris_offset)
  };
  FaceFit Fit(const cv::Mat& image, const Camera& camera, const Face& face, History* history, double timestamp_s);
  struct FreshFit {
    FitResult fit;
    bool free_vergence = false;  // fitted with the vergence free
  };
  // A fit from the face's landmarks (gaze search and all) with `options`, the
  // vergence free where `free_vergence` says or where the prior holds an iris
  // off its eye (free_vergence_iris_offset).
  FreshFit FitFresh(const cv::Mat& image, const Camera& camera, const Face& face, FitOptions options,
                    bool free_vergence);
  // Whether eyes at `opening` (a fraction of their usual opening) are closed in a blink.
  bool InABlink(double opening, double timestamp_s, History& history) const;

  std::shared_ptr<const EyeRegionModel> model_;
  GazeTrackerOptions options_;
  FaceTracker faces_;
  Fitter fresh_;
  Fitter warm_;
  Renderer renderer_;  // for IrisMisalignment
  std::map<int, History> histories_;
};

}  // namespace gazedirector
