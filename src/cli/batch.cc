#include "cli/batch.h"

#include <algorithm>
#include <exception>
#include <map>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include "cli/common.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/interrupt.h"

namespace gazedirector::cli {
namespace fs = std::filesystem;
namespace {

bool IsFolder(const fs::path& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

// What went wrong with an input, in a word or two, for the batch's summary.
std::string FailureWords(ExitCode code) {
  switch (code) {
    case ExitCode::kNoFace: return "no face";
    case ExitCode::kBadInput: return "bad input";
    case ExitCode::kOutput: return "output not written";
    default: return "internal error";
  }
}

}  // namespace

bool IsBatch(const std::vector<std::string>& inputs, const std::string& output) {
  return inputs.size() > 1 || std::any_of(inputs.begin(), inputs.end(), IsFolder) || IsFolder(output);
}

void AddBatchInputOptions(CLI::App& app, BatchInputOptions& options) {
  app.add_option("input", options.inputs, "Image or video files, or folders of them")->required();
  app.add_flag("-r,--recursive", options.recursive,
               "Read folders' subfolders too; their outputs go into subfolders of the same names");
}

std::vector<BatchInput> ExpandBatchInputs(const BatchInputOptions& options, const std::vector<std::string>& outputs) {
  const std::vector<fs::path> skipped(outputs.begin(), outputs.end());
  std::vector<BatchInput> expanded;
  for (const std::string& given : options.inputs) {
    if (!IsFolder(given)) {
      expanded.push_back({given, DetectMediaKind(given), "", fs::path(given).filename()});
      continue;
    }
    // One listing of the whole tree: without --recursive, what lies below is only counted.
    std::vector<fs::path> listed;
    std::size_t below = 0;
    for (const fs::path& path : MediaFilesIn(given, /*recursive=*/true, skipped)) {
      const bool nested = path.lexically_relative(given).has_parent_path();
      if (nested && !options.recursive) {
        ++below;
      } else {
        listed.push_back(path);
      }
    }
    if (listed.empty() && below > 0) {
      Fail(ExitCode::kBadInput, "{}: the folder holds no images or videos, but its subfolders hold {} (--recursive reads them)",
           given, below);
    }
    if (listed.empty()) Fail(ExitCode::kBadInput, "{}: the folder holds no images or videos", given);
    if (below > 0) spdlog::info("{}: {} image(s) or video(s) in its subfolders left out; --recursive reads them", given, below);
    for (const fs::path& path : listed) {
      const fs::path name = path.lexically_relative(given);
      try {
        expanded.push_back({path, DetectMediaKind(path), "", name});
      } catch (const Error& e) {
        expanded.push_back({path, HasVideoExtension(path) ? MediaKind::kVideo : MediaKind::kImage, e.what(), name});
      }
    }
  }
  return expanded;
}

void RequireFolderName(const std::string& folder, const std::string& option) {
  if (folder.empty() || IsFolder(folder)) return;
  const std::string extension = LowerExtension(folder);
  if (IsImagePath(folder) || HasVideoExtension(folder) || extension == ".json" || extension == ".jsonl" ||
      extension == ".csv") {
    Fail(ExitCode::kUsage, "{} {}: several inputs are written into a folder; name one", option, folder);
  }
}

fs::path BatchOutputPath(const fs::path& folder, const BatchInput& input, const std::string& extension) {
  fs::path name = input.name;
  if (!extension.empty()) return folder / name.replace_extension(extension);
  if (input.kind == MediaKind::kImage && !IsImagePath(name)) name.replace_extension(".png");
  if (input.kind == MediaKind::kVideo && !HasVideoExtension(name)) name.replace_extension(".mp4");
  return folder / name;
}

void RequireDistinctOutputs(const std::vector<BatchInput>& inputs, const std::vector<fs::path>& outputs) {
  std::map<fs::path, fs::path> writers;  // output -> its input
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const auto [claimed, fresh] = writers.emplace(outputs[i].lexically_normal(), inputs[i].path);
    if (!fresh) {
      Fail(ExitCode::kUsage, "{} and {} would both be written to {}: give them separately", claimed->second.string(),
           inputs[i].path.string(), outputs[i].string());
    }
  }
}

std::vector<AnalysisOutputs> PlanAnalysisOutputs(const std::vector<BatchInput>& inputs, const std::string& output,
                                                 const std::string& csv, const std::string& overlay) {
  RequireFolderName(output, "-o");
  RequireFolderName(csv, "--csv");
  RequireFolderName(overlay, "--overlay");
  std::vector<fs::path> outputs, csvs, overlays;
  for (const BatchInput& input : inputs) {
    outputs.push_back(BatchOutputPath(output, input, input.kind == MediaKind::kImage ? ".json" : ".jsonl"));
    if (!csv.empty()) csvs.push_back(BatchOutputPath(csv, input, ".csv"));
    if (!overlay.empty()) overlays.push_back(BatchOutputPath(overlay, input));
  }
  RequireDistinctOutputs(inputs, outputs);
  if (!csv.empty()) RequireDistinctOutputs(inputs, csvs);
  if (!overlay.empty()) RequireDistinctOutputs(inputs, overlays);
  RequireWritableFolder(output, "-o");
  RequireWritableFolder(csv, "--csv");
  RequireWritableFolder(overlay, "--overlay");
  std::vector<AnalysisOutputs> planned;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    AnalysisOutputs one{outputs[i].string(), csv.empty() ? "" : csvs[i].string(),
                        overlay.empty() ? "" : overlays[i].string()};
    RequireAnalysisOutputs(one.output, one.csv, one.overlay, inputs[i].kind, inputs[i].path.string());
    planned.push_back(one);
  }
  return planned;
}

int RunEachInput(const std::vector<BatchInput>& inputs, const std::function<int(std::size_t)>& run) {
  std::vector<std::string> failed;
  int exit_code = 0;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    ThrowIfInterrupted();
    const std::string name = inputs[i].name.string();
    int code = 0;
    {
      const ScopedLogPrefix prefix(fmt::format("[{}/{}] {}: ", i + 1, inputs.size(), name));
      try {
        if (!inputs[i].unreadable.empty()) throw Error(ExitCode::kBadInput, inputs[i].unreadable);
        code = run(i);
      } catch (const Error& e) {
        // These hold for every input alike.
        if (e.code() == ExitCode::kInterrupted || e.code() == ExitCode::kAssets || e.code() == ExitCode::kUsage) throw;
        spdlog::error("{}", e.what());
        code = static_cast<int>(e.code());
      } catch (const std::exception& e) {
        spdlog::error("internal error: {}", e.what());
        code = static_cast<int>(ExitCode::kInternal);
      }
    }
    if (code != 0) {
      failed.push_back(fmt::format("{} ({})", name, FailureWords(static_cast<ExitCode>(code))));
      if (exit_code == 0) exit_code = code;
    }
  }
  if (failed.empty()) {
    spdlog::info("all {} inputs done", inputs.size());
  } else {
    spdlog::warn("{} of {} inputs did not go through: {}", failed.size(), inputs.size(), fmt::join(failed, ", "));
  }
  return exit_code;
}

}  // namespace gazedirector::cli
