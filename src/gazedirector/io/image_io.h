#pragma once

#include <filesystem>
#include <vector>

#include <opencv2/core.hpp>

#include "gazedirector/io/photo_metadata.h"

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

// An image as its file holds it (any depth; 1, 3 or 4 channels) beside the
// 8-bit BGR copy that the pipeline reads and edits.
struct SourceImage {
  cv::Mat original;
  cv::Mat bgr;
};

// ReadImage, keeping the decoded original too.
SourceImage ReadSourceImage(const std::filesystem::path& path);

// `edited`, an edited copy of source.bgr, in the source's own depth and
// channels as far as the format of `output` holds them (16 bits: PNG and TIFF;
// alpha: PNG, TIFF and WebP; grayscale: all): the pixels the edit left alone keep
// their original values exactly and the alpha channel is the original's, so an
// edit loses nothing outside what it changed.
cv::Mat InSourceFormat(const SourceImage& source, const cv::Mat& edited, const std::filesystem::path& output);

// Writes atomically (temp file + rename); the format follows the extension.
void WriteImage(const std::filesystem::path& path, const cv::Mat& image,
                const std::vector<std::filesystem::path>& inputs = {});
// The same, carrying over the metadata of the photo it was made from (EXIF,
// XMP, ICC profile: PhotoMetadata), with a warning where the format cannot
// hold it.
void WriteImage(const std::filesystem::path& path, const cv::Mat& image, const PhotoMetadata& metadata,
                const std::vector<std::filesystem::path>& inputs = {});

}  // namespace gazedirector
