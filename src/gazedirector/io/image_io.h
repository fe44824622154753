#pragma once

#include <filesystem>
#include <vector>

#include <opencv2/core.hpp>

namespace gazedirector {

// Limits on what ReadImage accepts; outside them it fails with a clear error.
inline constexpr int kMinImageSide = 16;
inline constexpr double kMaxImageMegapixels = 256.0;

// Reads any image OpenCV can decode as 8-bit BGR: grayscale is replicated,
// 16-bit and float images are scaled, alpha is dropped, EXIF orientation is
// applied. Missing, empty, truncated, tiny or huge images fail with
// ExitCode::kBadInput and a one-line message.
cv::Mat ReadImage(const std::filesystem::path& path);

// Converts a decoded image of any depth and channel count to 8-bit BGR.
cv::Mat ToBgr8(const cv::Mat& image);

// Writes atomically (temp file + rename); the format follows the extension.
void WriteImage(const std::filesystem::path& path, const cv::Mat& image,
                const std::vector<std::filesystem::path>& inputs = {});

}  // namespace gazedirector
