#include "gazedirector/io/atomic_output.h"

#include <unistd.h>

#include <fstream>
#include <system_error>

#include "gazedirector/util/error.h"

namespace gazedirector {
namespace fs = std::filesystem;

void RequireNotAnInput(const fs::path& path, const std::vector<fs::path>& inputs) {
  std::error_code ec;
  if (path.empty() || !fs::exists(path, ec)) return;
  for (const fs::path& input : inputs) {
    if (fs::equivalent(path, input, ec)) {
      Fail(ExitCode::kOutput, "refusing to overwrite the input {}; choose another output path", path.string());
    }
  }
}

AtomicOutput::AtomicOutput(const fs::path& path, const std::vector<fs::path>& inputs) : path_(path) {
  if (path.empty()) Fail(ExitCode::kOutput, "empty output path");
  std::error_code ec;
  if (fs::is_directory(path, ec)) Fail(ExitCode::kOutput, "cannot write {}: it is a folder", path.string());
  RequireNotAnInput(path, inputs);
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  fs::create_directories(parent, ec);
  if (!fs::is_directory(parent)) Fail(ExitCode::kOutput, "cannot create the output folder {}", parent.string());
  temp_path_ = parent / fmt::format(".{}.partial-{}{}", path.stem().string(), ::getpid(), path.extension().string());
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_path_, ec);
  }
}

void AtomicOutput::Commit() {
  std::error_code ec;
  if (!fs::exists(temp_path_, ec)) Fail(ExitCode::kOutput, "nothing was written for {}", path_.string());
  fs::rename(temp_path_, path_, ec);
  if (ec) Fail(ExitCode::kOutput, "cannot write {}: {}", path_.string(), ec.message());
  committed_ = true;
}

void RequireWritable(const fs::path& path, const std::vector<fs::path>& inputs) {
  const AtomicOutput probe(path, inputs);  // its destructor removes the probe file
  std::ofstream stream(probe.temp_path(), std::ios::binary);
  if (!stream) {
    Fail(ExitCode::kOutput, "cannot write {}: no new file can be made in {}", path.string(),
         probe.temp_path().parent_path().string());
  }
}

void WriteTextFile(const fs::path& path, const std::string& text, const std::vector<fs::path>& inputs) {
  AtomicOutput output(path, inputs);
  {
    std::ofstream stream(output.temp_path(), std::ios::binary);
    stream << text;
    if (!stream.good()) Fail(ExitCode::kOutput, "cannot write {}", path.string());
  }
  output.Commit();
}

}  // namespace gazedirector
