#include "gazedirector/util/temporary_folder.h"

#include <unistd.h>

#include <atomic>
#include <system_error>

namespace gazedirector {

std::filesystem::path TemporaryFolder() {
  std::error_code ec;
  const std::filesystem::path folder = std::filesystem::temp_directory_path(ec);
  if (!ec && std::filesystem::is_directory(folder, ec)) return folder;
  return "/tmp";
}

std::filesystem::path UniqueTemporaryPath(const std::string& suffix) {
  static std::atomic<long> counter = 0;
  return TemporaryFolder() / ("gazedirector-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + suffix);
}

}  // namespace gazedirector
