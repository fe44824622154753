#pragma once

#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace gazedirector {

// Process exit codes of the `gazedirector` program, documented in README.md.
enum class ExitCode : int {
  kOk = 0,
  kInternal = 1,      // a bug or an unexpected failure
  kUsage = 2,         // bad command line
  kNoFace = 3,        // ran cleanly, found no face (outputs are still written)
  kBadInput = 4,      // missing, unreadable, truncated or unsupported input
  kAssets = 5,        // model assets missing or invalid
  kOutput = 6,        // an output could not be written
  kInterrupted = 130  // stopped by SIGINT/SIGTERM; no partial output is left
};

// An error a user can act on. `what()` is one line and names the culprit.
class Error : public std::runtime_error {
 public:
  Error(ExitCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ExitCode code() const { return code_; }

 private:
  ExitCode code_;
};

template <typename... Args>
[[noreturn]] void Fail(ExitCode code, fmt::format_string<Args...> format, Args&&... args) {
  throw Error(code, fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace gazedirector
