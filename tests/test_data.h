#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "gazedirector/face/landmark_detector.h"
#include "gazedirector/io/assets.h"

namespace gazedirector::testing {

// The real data beside the repository (../shared), as the build found it.
std::filesystem::path SharedDir();
std::filesystem::path DataPath(const std::string& relative);  // under ../shared/data
const Assets& TestAssets();
// One landmark model per test binary: loading it takes half a second.
std::shared_ptr<const LandmarkDetector> SharedLandmarkDetector();
// A fresh folder under the build tree's temp dir, removed with the process.
std::filesystem::path ScratchDir(const std::string& name);
// The gazedirector program built beside the tests.
std::filesystem::path CliPath();

// Runs the CLI with `arguments` (shell-quoted by the caller); returns its exit
// code and fills `output` with stdout+stderr.
int RunCli(const std::string& arguments, std::string* output = nullptr);
// A path in single quotes, for RunCli's shell.
std::string Quote(const std::filesystem::path& path);
// True when no temporary ".partial" file is left anywhere under `dir`.
bool NoPartialFiles(const std::filesystem::path& dir);

}  // namespace gazedirector::testing
