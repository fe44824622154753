#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace gazedirector {

// An output file that appears only when complete: writers fill temp_path(),
// Commit() renames it over the final path, and an uncommitted temp file is
// removed on destruction (errors and interrupts never leave partial files).
// The temp name keeps the extension so that encoders choose the right format.
class AtomicOutput {
 public:
  // Creates the parent folder when needed. Fails (ExitCode::kOutput) when the
  // path is a folder or when it names one of `inputs`, which are never modified.
  explicit AtomicOutput(const std::filesystem::path& path,
                        const std::vector<std::filesystem::path>& inputs = {});
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& temp_path() const { return temp_path_; }
  void Commit();

 private:
  std::filesystem::path path_;
  std::filesystem::path temp_path_;
  bool committed_ = false;
};

// Fails (ExitCode::kOutput) when `path` names one of `inputs` (the same file,
// through any link), which are never modified; AtomicOutput checks this too,
// but commands check their outputs before the work, not after it.
void RequireNotAnInput(const std::filesystem::path& path, const std::vector<std::filesystem::path>& inputs);

// Fails (ExitCode::kOutput) unless a file can be written at `path`: not a
// folder, not one of `inputs`, and its folder (created when missing) takes new
// files. Commands check each output with this before their work, so that a bad
// path fails at once instead of after minutes of fitting.
void RequireWritable(const std::filesystem::path& path, const std::vector<std::filesystem::path>& inputs = {});

// Writes `text` to `path` atomically.
void WriteTextFile(const std::filesystem::path& path, const std::string& text,
                   const std::vector<std::filesystem::path>& inputs = {});

}  // namespace gazedirector
