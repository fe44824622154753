#pragma once

// Commands run on several inputs, or folders of them: each input is written
// into output folders under its own name, as a run on it alone writes it.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "gazedirector/io/media.h"

namespace gazedirector::cli {

struct BatchInput {
  std::filesystem::path path;
  MediaKind kind;
  std::string unreadable;      // why a file found in a folder cannot be read (empty: it can); its turn reports it
  std::filesystem::path name;  // its outputs' name in an output folder: its file name, or its path in the folder given
};

// A batch's inputs as given: files, or folders of them, with or without their
// subfolders.
struct BatchInputOptions {
  std::vector<std::string> inputs;
  bool recursive = false;
};
// Adds the inputs and --recursive to a command.
void AddBatchInputOptions(CLI::App& app, BatchInputOptions& options);

// Whether a command line asks for a batch: several inputs, a folder among
// them, or an output that is an existing folder.
bool IsBatch(const std::vector<std::string>& inputs, const std::string& output);

// The inputs as given, each folder replaced by its images and videos
// (MediaFilesIn; with --recursive those of its subfolders too, but not of the
// `outputs` folders), each with its kind. Fails with a bad-input error for a
// missing or unrecognised file given by name, or a folder with nothing to
// read; a file in a folder that cannot be read (empty, say) is marked so and
// fails in its turn, as one that cannot be decoded does.
std::vector<BatchInput> ExpandBatchInputs(const BatchInputOptions& options, const std::vector<std::string>& outputs);

// Fails with a usage error where `folder` (given as `option`) is named like a
// file (out.jpg, fits.json) and is no existing folder. An empty name passes.
void RequireFolderName(const std::string& folder, const std::string& option);

// An input's output in `folder`: its name (in a subfolder where it was in
// one) with `extension` (".json"), or, where that is empty, its whole name,
// made a PNG or an MP4 where its format is one we read but do not write.
std::filesystem::path BatchOutputPath(const std::filesystem::path& folder, const BatchInput& input,
                                      const std::string& extension = "");

// Fails with a usage error where two inputs would be written to one file
// (`outputs[i]` is `inputs[i]`'s).
void RequireDistinctOutputs(const std::vector<BatchInput>& inputs, const std::vector<std::filesystem::path>& outputs);

// The outputs of `landmarks` and `track` for each input of a batch: -o, --csv
// and --overlay name folders (the last two may be empty: not written), each
// checked as RequireAnalysisOutputs checks one input's, the folders made.
struct AnalysisOutputs {
  std::string output, csv, overlay;
};
std::vector<AnalysisOutputs> PlanAnalysisOutputs(const std::vector<BatchInput>& inputs, const std::string& output,
                                                 const std::string& csv, const std::string& overlay);

// A command's options for one input of a batch: its input and its outputs
// (PlanAnalysisOutputs) put in.
template <typename Options>
Options OptionsForInput(Options options, const BatchInput& input, const AnalysisOutputs& outputs) {
  options.input = input.path.string();
  options.output = outputs.output;
  options.csv = outputs.csv;
  options.overlay = outputs.overlay;
  return options;
}

// Runs `run(i)` on each input in turn, its log lines prefixed "[k/n] name: ".
// An input that fails (an error, or a non-zero exit code returned) is
// reported and the others go on; returns the first failure's exit code. An
// interruption, missing model assets and a usage error (bad camera options,
// say) stop the batch.
int RunEachInput(const std::vector<BatchInput>& inputs, const std::function<int(std::size_t)>& run);

}  // namespace gazedirector::cli
