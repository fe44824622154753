#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gazedirector {

enum class MediaKind { kImage, kVideo };

// What a file holds, judged by its first bytes (then its extension). Fails
// with ExitCode::kBadInput for a missing, empty or unrecognised file.
MediaKind DetectMediaKind(const std::filesystem::path& path);

// The path's extension in lower case, with its dot ("photo.JPG" -> ".jpg").
std::string LowerExtension(const std::filesystem::path& path);

// True when the path's extension names an image format we read (".jpg", ".png", ...).
bool HasImageExtension(const std::filesystem::path& path);

// The video containers we can write, by extension (".mp4", ...).
const std::vector<std::string>& VideoExtensions();
// True when the path's extension names one of them.
bool HasVideoExtension(const std::filesystem::path& path);

// The files in `folder` (not hidden ones), sorted by path; with `recursive`
// those of its subfolders too, but not of hidden ones or of the `skipped`
// folders (a batch's outputs inside it). Fails with ExitCode::kBadInput when
// the folder cannot be read.
std::vector<std::filesystem::path> FilesIn(const std::filesystem::path& folder, bool recursive = false,
                                           const std::vector<std::filesystem::path>& skipped = {});
// The images and videos among them, by extension.
std::vector<std::filesystem::path> MediaFilesIn(const std::filesystem::path& folder, bool recursive = false,
                                                const std::vector<std::filesystem::path>& skipped = {});

struct ImageHeader {
  std::string format;  // "jpeg", "png", ...
  int width = 0;
  int height = 0;
  bool complete = true;  // false when the file ends before the image data does
};

// Reads the size from a JPEG or PNG header without decoding; nullopt for
// other formats. Used to refuse oversized and truncated images cheaply.
std::optional<ImageHeader> ProbeImageHeader(const std::filesystem::path& path);

}  // namespace gazedirector
