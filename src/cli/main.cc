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

// Every command `parent` holds (CLI11's plain get_subcommands() gives the parsed ones).
std::vector<CLI::App*> CommandsOf(CLI::App* parent) {
  return parent->get_subcommands([](CLI::App*) { return true; });
}

// The command the words of argv name, as far as they name one (the program
// itself when none); `unknown` gets the first word that names none where a
// command belongs.
CLI::App* NamedCommand(CLI::App& app, int argc, char** argv, std::string* unknown = nullptr) {
  CLI::App* current = &app;
  for (int i = 1; i < argc && argv[i][0] != '-'; ++i) {
    const std::vector<CLI::App*> commands = CommandsOf(current);
    if (commands.empty()) break;
    const auto named = std::find_if(commands.begin(), commands.end(),
                                    [&](CLI::App* command) { return command->get_name() == argv[i]; });
    if (named == commands.end()) {
      if (unknown != nullptr) *unknown = argv[i];
      break;
    }
    current = *named;
  }
  return current;
}

// "landmarks, bench, ...": the commands `parent` holds.
std::string CommandNames(CLI::App* parent) {
  std::vector<std::string> names;
  for (CLI::App* command : CommandsOf(parent)) names.push_back(command->get_name());
  return fmt::format("{}", fmt::join(names, ", "));
}

// "command" for the program's commands, "eval command" for eval's.
std::string CommandWord(CLI::App& app, CLI::App* parent) {
  return parent == &app ? "command" : parent->get_name() + " command";
}

// A word where a command (or an eval's kind) belongs that names none: CLI11
// would only say "A subcommand is required". Returns whether it reported one.
bool ReportUnknownCommand(CLI::App& app, int argc, char** argv) {
  std::string unknown;
  CLI::App* current = NamedCommand(app, argc, argv, &unknown);
  if (unknown.empty()) return false;
  fmt::print(stderr, "gazedirector: error: unknown {} '{}' (one of {})\n", CommandWord(app, current), unknown,
             CommandNames(current));
  return true;
}

// "gazedirector eval columbia" for the command argv names.
std::string CommandLine(CLI::App& app, int argc, char** argv) {
  std::vector<std::string> words;
  for (CLI::App* command = NamedCommand(app, argc, argv); command != nullptr; command = command->get_parent()) {
    words.insert(words.begin(), command->get_name());
  }
  return fmt::format("{}", fmt::join(words, " "));
}

// A usage error in one line, as every other error, with where to read more
// (CLI11 prints its message and "Run with --help for more information.").
int ReportUsageError(CLI::App& app, const CLI::ParseError& error, int argc, char** argv) {
  std::string message = error.what();
  std::replace(message.begin(), message.end(), '\n', ' ');
  CLI::App* command = NamedCommand(app, argc, argv);
  const bool lacks_command = dynamic_cast<const CLI::RequiredError*>(&error) != nullptr &&
                             !CommandsOf(command).empty() && command->get_subcommands().empty();
  if (lacks_command) {
    message = fmt::format("no {} given: one of {}", CommandWord(app, command), CommandNames(command));
  }
  fmt::print(stderr, "gazedirector: error: {} (see {} --help)\n", message, CommandLine(app, argc, argv));
  return static_cast<int>(gazedirector::ExitCode::kUsage);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace gazedirector;
  spdlog::set_default_logger(spdlog::stderr_color_mt("gazedirector"));
  cli::SetLogPrefix("");
  cv::setNumThreads(2);
  InstallInterruptHandlers();

  CLI::App app("GazeDirector: find faces, fit a 3D eye-region model and redirect gaze in photos and videos.",
               "gazedirector");
  app.require_subcommand(1);
  app.set_version_flag("--version", "gazedirector 0.1.0");
  // --help lists them in this order: what most users run first, then the
  // tools that measure it.
  std::vector<cli::Command> commands = {cli::RegisterRedirectCommand(app), cli::RegisterTrackCommand(app),
                                        cli::RegisterLandmarksCommand(app), cli::RegisterRenderCommand(app),
                                        cli::RegisterBenchCommand(app), cli::RegisterEvalCommand(app),
                                        cli::RegisterTrainCommand(app)};
  if (ReportUnknownCommand(app, argc, argv)) return static_cast<int>(ExitCode::kUsage);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    return ReportUsageError(app, e, argc, argv);
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
