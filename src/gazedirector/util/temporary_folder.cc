#include "gazedirector/util/temporary_folder.h"

#include <system_error>

namespace gazedirector {

std::filesystem::path TemporaryFolder() {
  std::error_code ec;
  const std::filesystem::path folder = std::filesystem::temp_directory_path(ec);
  if (!ec && std::filesystem::is_directory(folder, ec)) return folder;
  return "/tmp";
}

}  // namespace gazedirector
