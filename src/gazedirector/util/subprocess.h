#pragma once

#include <sys/types.h>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gazedirector {

// A child program fed through a pipe to its stdin (for example ffmpeg
// encoding raw frames). It runs in its own process group so that a Ctrl-C at
// the terminal reaches only us, and we decide how it ends. Its stderr is kept
// in a temporary file for error messages. The destructor kills a child that
// was not finished.
class Subprocess {
 public:
  explicit Subprocess(const std::vector<std::string>& argv);
  ~Subprocess();
  Subprocess(const Subprocess&) = delete;
  Subprocess& operator=(const Subprocess&) = delete;

  // False when the child has gone away.
  bool Write(const void* data, std::size_t size);
  // Closes stdin and waits; returns the exit status (-1 when killed by a signal).
  int Finish();
  void Kill();
  // The last lines the child wrote to stderr.
  std::string ErrorOutput() const;

 private:
  pid_t pid_ = -1;
  int stdin_fd_ = -1;
  std::filesystem::path stderr_path_;
};

// Runs a program to its end with nothing on its stdin and returns what it
// wrote to stdout, or nothing when it could not start or exited non-zero (its
// stderr is discarded). For quick queries such as ffprobe's.
std::optional<std::string> RunForOutput(const std::vector<std::string>& argv);

// True when `program` is found in PATH.
bool ProgramExists(const std::string& program);

}  // namespace gazedirector
