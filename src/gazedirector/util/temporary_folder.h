#pragma once

#include <filesystem>

namespace gazedirector {

// Where temporary files go: $TMPDIR (as std::filesystem::temp_directory_path
// reads it) where that is a folder, else /tmp. A $TMPDIR that names no folder
// made every video command fail with an internal filesystem error.
std::filesystem::path TemporaryFolder();

}  // namespace gazedirector
