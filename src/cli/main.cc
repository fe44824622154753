// gazedirector: changes where people in photos and videos are looking.
#include <cstdio>
#include <exception>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/core/utility.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "cli/common.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/interrupt.h"

int main(int argc, char** argv) {
  using namespace gazedirector;
  spdlog::set_pattern("%^%l%$: %v");
  spdlog::set_default_logger(spdlog::stderr_color_mt("gazedirector"));
  spdlog::set_pattern("%^%l%$: %v");
  cv::setNumThreads(2);
  InstallInterruptHandlers();

  CLI::App app("GazeDirector: find faces, fit a 3D eye-region model and redirect gaze in photos and videos.",
               "gazedirector");
  app.require_subcommand(1);
  app.set_version_flag("--version", "gazedirector 0.1.0");
  std::vector<cli::Command> commands = {cli::RegisterLandmarksCommand(app), cli::RegisterBenchCommand(app),
                                        cli::RegisterEvalCommand(app), cli::RegisterRenderCommand(app),
                                        cli::RegisterTrackCommand(app), cli::RegisterRedirectCommand(app),
                                        cli::RegisterTrainCommand(app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : static_cast<int>(ExitCode::kUsage);
  }
  try {
    for (const cli::Command& command : commands) {
      if (command.app->parsed()) return command.run();
    }
    return static_cast<int>(ExitCode::kUsage);
  } catch (const Error& e) {
    std::fprintf(stderr, "gazedirector: error: %s\n", e.what());
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gazedirector: internal error: %s\n", e.what());
    return static_cast<int>(ExitCode::kInternal);
  }
}
