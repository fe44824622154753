#include "cli/fitting.h"

#include "gazedirector/fit/fit_options.h"
#include "gazedirector/io/assets.h"
#include "gazedirector/util/error.h"

namespace gazedirector::cli {

void AddFittingOptions(CLI::App& command, FittingOptions& options) {
  command.add_flag("--largest", options.largest, "Only the largest face");
  AddHeadPoseOption(command, options.head_pose);
  command.add_option("--fit", options.fit, "Fitter option name=value (repeatable); `gazedirector eval columbia --help` lists them");
  command.add_option("--warm-fit", options.warm_fit, "The same for video frames fitted from the previous frame's fit");
}

FittingSetup FittingSetup::Create(const CommonOptions& common, const FittingOptions& options) {
  const Assets assets = Assets::Resolve(common.assets);
  FittingSetup setup;
  for (const std::string& assignment : options.fit) {
    SetFitOption(setup.tracker_options.fresh, assignment);
  }
  for (const std::string& assignment : options.warm_fit) {
    SetFitOption(setup.tracker_options.warm, assignment);
  }
  setup.largest = options.largest;
  setup.tracker_options.head_pose = options.head_pose;
  setup.model_loading_ = std::async(std::launch::async, [assets] { return EyeRegionModel::Load(assets); }).share();
  setup.faces = FaceModels::Load(assets);
  return setup;
}

GazeTracker FittingSetup::MakeTracker() const {
  return GazeTracker(model(), faces.landmarks, faces.mean_face, tracker_options, nullptr, largest);
}

std::vector<FaceFit> FittingSetup::FitImage(const cv::Mat& image, const Camera& camera) const {
  FaceTracker tracker(faces.landmarks, faces.mean_face, GazeTracker::FaceOptions(largest, tracker_options.head_pose));
  const std::vector<Face> found = tracker.DetectFaces(image, camera);
  return MakeTracker().FitImageFaces(image, camera, found);
}

void RequireFitsOfSize(const FitsFile& fits, int width, int height) {
  if (fits.camera && (fits.camera->width != width || fits.camera->height != height)) {
    Fail(ExitCode::kBadInput, "the fits were made on {}x{} frames, the input has {}x{}", fits.camera->width,
         fits.camera->height, width, height);
  }
}

}  // namespace gazedirector::cli
