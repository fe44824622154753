#pragma once

#include <future>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/common.h"
#include "gazedirector/face/landmark_detector.h"
#include "gazedirector/face/mean_face.h"
#include "gazedirector/io/fit_io.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/video/gaze_tracker.h"

namespace gazedirector::cli {

// The options of the commands that fit the model (track, redirect).
struct FittingOptions {
  bool largest = false;
  HeadPoseMethod head_pose = HeadPoseMethod::kPerspectiveNPoint;
  std::vector<std::string> fit;  // name=value fitter options
  std::vector<std::string> warm_fit;  // the same for warm-started video frames
};
void AddFittingOptions(CLI::App& command, FittingOptions& options);

// What fitting needs, loaded once. The eye-region model (about 0.2 s) loads
// in the background from Create on, while the input is opened and its faces
// searched for; model() waits for it and rethrows its errors.
struct FittingSetup {
  FaceModels faces;
  GazeTrackerOptions tracker_options;
  bool largest = false;

  static FittingSetup Create(const CommonOptions& common, const FittingOptions& options);
  const std::shared_ptr<const EyeRegionModel>& model() const { return model_loading_.get(); }
  GazeTracker MakeTracker() const;
  // A still's faces found and fitted (GazeTracker::ProcessImage), the faces
  // searched for before the model is waited for.
  std::vector<FaceFit> FitImage(const cv::Mat& image, const Camera& camera) const;

 private:
  std::shared_future<std::shared_ptr<const EyeRegionModel>> model_loading_;
};

// Fails with a bad-input error when `fits` were made on frames of another
// size: they belong to another input, whose eyes sit elsewhere.
void RequireFitsOfSize(const FitsFile& fits, int width, int height);

}  // namespace gazedirector::cli
