// `gazedirector train-appearance`: trains the appearance gaze prior on labelled
// Columbia crops and writes it, as the build makes build/release/models/appearance_gaze.cbor.
#include <memory>

#include <spdlog/spdlog.h>

#include "cli/common.h"
#include "gazedirector/eval/columbia.h"
#include "gazedirector/fit/appearance_gaze.h"
#include "gazedirector/io/atomic_output.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/timer.h"

namespace gazedirector::cli {
namespace {

struct TrainOptions {
  CommonOptions common;
  std::string dir;
  std::string output;
  double ridge = 0.1;
};

int RunTrainAppearance(const TrainOptions& options) {
  ApplyLogLevel(options.common);
  if (!(options.ridge > 0 && options.ridge < 1e9)) {
    Fail(ExitCode::kUsage, "--ridge {}: expected a number above 0 and below 1e9", options.ridge);
  }
  RequireWritable(options.output);
  // Fails unless it is a folder with crops in it.
  const std::vector<ColumbiaCrop> crops = ListColumbia(ColumbiaDirOrDefault(options.dir));
  Timer timer;
  AppearanceGazeTrainer trainer(options.ridge);
  AddColumbiaCrops(crops, trainer);
  const AppearanceGaze model = trainer.Solve();
  model.Save(options.output);
  spdlog::info("trained on {} crops of {} subjects ({} of them with the head facing the camera) in {:.1f} s; wrote {}",
               model.samples().pitch, model.subjects().size(), model.samples().frontal_yaw, timer.Seconds(),
               options.output);
  return 0;
}

}  // namespace

Command RegisterTrainCommand(CLI::App& root) {
  auto options = std::make_shared<TrainOptions>();
  CLI::App* app = root.add_subcommand(
      "train-appearance",
      "Train the appearance gaze prior of eye-patch fits on labelled Columbia crops (gaze pitch and yaw, and the head's yaw, from every head pose)");
  app->add_option("dir", options->dir, "Folder of crops, its subfolders included (default: ../shared/data/columbia-eyes)");
  app->add_option("-o,--output", options->output, "Write the model here (CBOR)")->required();
  app->add_option("--ridge", options->ridge, "Ridge penalty of the kernel regressions (added to the kernel's diagonal)")
      ->capture_default_str();
  AddCommonOptions(*app, options->common);
  return {app, [options] { return RunTrainAppearance(*options); }};
}

}  // namespace gazedirector::cli
