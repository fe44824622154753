#pragma once

#include <filesystem>
#include <string>

namespace gazedirector {

// Where temporary files go: $TMPDIR (as std::filesystem::temp_directory_path
// reads it) where that is a folder, else /tmp. A $TMPDIR that names no folder
// made every video command fail with an internal filesystem error.
std::filesystem::path TemporaryFolder();

// A path in TemporaryFolder() that no other temporary file of this process
// takes: "gazedirector-<pid>-<n><suffix>". Nothing is created there.
std::filesystem::path UniqueTemporaryPath(const std::string& suffix);

}  // namespace gazedirector
