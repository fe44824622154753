// gazedirector eval: accuracy figures on the real data, printed as numbers.
// Each evaluation runs in its own file (eval_options.h lists them).
#include <memory>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cli/eval_options.h"
#include "gazedirector/fit/fit_options.h"
#include "gazedirector/util/error.h"

namespace gazedirector::cli {

namespace {

CLI::App* AddLandmarkEval(CLI::App& eval, EvalOptions& options) {
  CLI::App* landmarks = eval.add_subcommand("landmarks", "68-point landmark error on hand-marked faces (dlib XML)");
  landmarks->add_option("xml", options.landmarks_xml,
                        "dlib XML with marked faces (default: ../shared/data/dlib-faces/testing_with_face_landmarks.xml)");
  landmarks->add_flag("--json", options.json, "Print one JSON object");
  landmarks->add_option("--turn", options.landmark_turns,
                        "Also turn each photo by these angles in degrees first (e.g. 0 30 60 90): tilted faces")
      ->check(CLI::Range(-180.0, 180.0))
      ->capture_default_str();
  AddCommonOptions(*landmarks, options.common);
  return landmarks;
}

// What both Columbia evaluations take: the crops, which subjects, the fitter's options.
void AddColumbiaOptions(CLI::App& command, EvalOptions& options) {
  command.add_option("dir", options.columbia_dir, "Folder of crops, its subfolders included (default: ../shared/data/columbia-eyes)");
  command.add_flag("--json", options.json, "Print one JSON object");
  command.add_option("--subjects", options.subjects, "Only these subjects (e.g. 0001 0002)");
  command.add_option("--exclude-subjects", options.excluded_subjects,
                     "Leave these subjects out (the paper left out people wearing glasses)");
  command.add_option("--fit", options.fit_options,
                     "Fitter options as name=value (" + fmt::format("{}", fmt::join(ListFitOptions(), ", ")) + ")");
}

CLI::App* AddColumbiaEval(CLI::App& eval, EvalOptions& options) {
  CLI::App* columbia = eval.add_subcommand("columbia", "Gaze estimation error on Columbia Gaze eye crops (file-name labels)");
  AddColumbiaOptions(*columbia, options);
  columbia->add_option("--plot", options.plot, "Write the convergence figure here (PNG)")->capture_default_str();
  columbia->add_option("--csv", options.csv, "Write every crop's estimate and error here");
  columbia->add_option("--poses", options.poses, "Only these head poses (e.g. 0 15)");
  columbia->add_option("--every", options.every, "Take every Nth photo, both eyes' crops (a quick, spread-out sample)")
      ->check(CLI::Range(1, 1000000));
  columbia->add_option("--threads", options.threads, "Fits side by side")->check(CLI::Range(1, 64))->capture_default_str();
  columbia->add_option("--iterations", options.iterations, "Gauss-Newton iterations per fit (default: the fitter's)");
  columbia->add_option("--appearance-training", options.appearance_training,
                       "Labelled crops to train the appearance gaze prior on, each evaluated subject left out "
                       "(default: ../shared/data/columbia-eyes; without it, the model the build trained, build/release/models/appearance_gaze.cbor)");
  columbia->add_flag("--known-head-pose", options.known_head_pose,
                     "Give the fitter the head's yaw from the file name (-P) instead of reading it from the photo's two crops");
  AddCommonOptions(*columbia, options.common);
  return columbia;
}

CLI::App* AddRedirectColumbiaEval(CLI::App& eval, EvalOptions& options) {
  CLI::App* redirect = eval.add_subcommand("redirect-columbia",
                                           "Redirection error on Columbia crops: each subject's 0V 0H crop redirected to the other gazes");
  AddColumbiaOptions(*redirect, options);
  redirect->add_option("--plot", options.cdf_plot, "Write the cumulative error curves here (PNG)")->capture_default_str();
  redirect->add_option("--out-dir", options.out_dir, "Write every redirected crop (c), framed as its source (unregistered), under the name of the real crop it imitates");
  redirect->add_option("--csv", options.csv, "Write every crop's three errors here");
  redirect->add_option("--eyelid-follow-down", options.redirect.eyelid_follow.down,
                       "How far the eyelids follow a downward change of pitch (0: not at all, 1: fully)")
      ->check(CLI::Range(0.0, 1.5))
      ->capture_default_str();
  redirect->add_option("--eyelid-follow-up", options.redirect.eyelid_follow.up, "The same for an upward change")
      ->check(CLI::Range(0.0, 1.5))
      ->capture_default_str();
  redirect->add_flag("--no-register", [&options](std::int64_t) { options.redirect.register_crops = false; },
                     "Compare with the real crops as cut, without registering them to the source crop on the skin around the eye");
  redirect->add_option("--angle-scale", options.redirect.angle_scale,
                       "Redirect by this fraction of each label's change of gaze (analysis; the evaluation is 1)")
      ->check(CLI::Range(0.0, 2.0))
      ->capture_default_str();
  AddCommonOptions(*redirect, options.common);
  return redirect;
}

CLI::App* AddIrisEval(CLI::App& eval, EvalOptions& options) {
  CLI::App* iris = eval.add_subcommand(
      "iris", "How far each fitted iris sits from the photo's own (no labels): images and videos");
  iris->add_option("input", options.iris_input, "Image or video")->required();
  iris->add_option("--fits", options.iris_fits, "Fits from `gazedirector track` of this input (default: track it now)");
  iris->add_option("--every", options.every, "Measure every Nth frame (a video is still tracked frame by frame)")
      ->check(CLI::Range(1, 1000000));
  iris->add_flag("--json", options.json, "Print one JSON object");
  iris->add_option("--csv", options.csv, "Write each measured eye's distance here (frame, face_id, eye, iris_misalignment)");
  AddFittingOptions(*iris, options.fitting);
  AddCameraOptions(*iris, options.camera);
  AddCommonOptions(*iris, options.common);
  return iris;
}

}  // namespace

Command RegisterEvalCommand(CLI::App& root) {
  // Shared by the subcommands' options and the run below, which outlive this call.
  auto options = std::make_shared<EvalOptions>();
  CLI::App* app = root.add_subcommand("eval", "Accuracy evaluations on the real data (numbers, not tests)");
  app->require_subcommand(1);
  CLI::App* landmarks = AddLandmarkEval(*app, *options);
  CLI::App* columbia = AddColumbiaEval(*app, *options);
  CLI::App* redirect = AddRedirectColumbiaEval(*app, *options);
  CLI::App* iris = AddIrisEval(*app, *options);
  return {app, [options, landmarks, columbia, redirect, iris] {
            if (landmarks->parsed()) return RunLandmarkEval(*options);
            if (columbia->parsed()) return RunColumbiaEval(*options);
            if (redirect->parsed()) return RunRedirectColumbiaEval(*options);
            if (iris->parsed()) return RunIrisEval(*options);
            return static_cast<int>(ExitCode::kUsage);
          }};
}

}  // namespace gazedirector::cli
