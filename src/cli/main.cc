// gazedirector: changes where people in photos and videos are looking.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <opencv2/core/utility.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "cli/common.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/interrupt.h"

namespace {

// A word where a command (or an eval's kind) belongs that names none: CLI11
// would only say "A subcommand is required". Returns whether it reported one.
bool ReportUnknownCommand(CLI::App& app, int argc, char** argv) {
  CLI::App* current = &app;
  for (int i = 1; i < argc && argv[i][0] != '-'; ++i) {
    const std::vector<CLI::App*> commands = current->get_subcommands([](CLI::App*) { return true; });
    if (commands.empty()) return false;
    const auto named = std::find_if(commands.begin(), commands.end(),
                                    [&](CLI::App* command) { return command->get_name() == argv[i]; });
    if (named == commands.end()) {
      std::vector<std::string> names;
      for (CLI::App* command : commands) names.push_back(command->get_name());
      const std::string where = current == &app ? "command" : current->get_name() + " command";
      fmt::print(stderr, "gazedirector: error: unknown {} '{}' (one of {})\n", where, argv[i], fmt::join(names, ", "));
      return true;
    }
    current = *named;
  }
  return false;
}

}  // namespace

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
  if (ReportUnknownCommand(app, argc, argv)) return static_cast<int>(ExitCode::kUsage);
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
