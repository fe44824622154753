// What the `gazedirector eval` subcommands share: their options, and the
// start of both Columbia evaluations. Each evaluation has its own file.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/common.h"
#include "cli/fitting.h"
#include "gazedirector/eval/columbia.h"
#include "gazedirector/eval/redirect_columbia.h"
#include "gazedirector/fit/fit_options.h"
#include "gazedirector/model/eye_region_model.h"

namespace gazedirector::cli {

// The options of every eval subcommand (each reads the ones it registers).
struct EvalOptions {
  CommonOptions common;
  bool json = false;
  std::string landmarks_xml;
  std::vector<double> landmark_turns = {0};
  std::string columbia_dir;
  std::string plot = "eval_columbia.png";
  std::string csv;
  std::vector<std::string> subjects;
  std::vector<std::string> excluded_subjects;
  std::vector<int> poses;
  int every = 1;
  int threads = 2;
  int iterations = 0;
  std::vector<std::string> fit_options;
  bool known_head_pose = false;
  std::string appearance_training;
  std::string out_dir;
  RedirectColumbiaOptions redirect;
  std::string cdf_plot = "eval_redirect_columbia.png";
  std::string iris_input;
  std::string iris_fits;
  FittingOptions fitting;
  CameraOptions camera;
};

// What both Columbia evaluations start from.
struct ColumbiaRun {
  std::filesystem::path dir;
  std::vector<ColumbiaCrop> listed;  // every crop in dir
  std::vector<ColumbiaCrop> crops;   // those the filters chose
  std::shared_ptr<const EyeRegionModel> model;
  FitOptions fit_options;
};
ColumbiaRun PrepareColumbiaRun(const EvalOptions& options);

int RunColumbiaEval(const EvalOptions& options);          // eval_columbia.cc
int RunRedirectColumbiaEval(const EvalOptions& options);  // eval_redirect_columbia.cc
int RunLandmarkEval(const EvalOptions& options);          // eval_landmarks.cc
int RunIrisEval(const EvalOptions& options);              // eval_iris.cc

}  // namespace gazedirector::cli
