#include "gazedirector/io/image_io.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "gazedirector/io/atomic_output.h"
#include "gazedirector/io/media.h"
#include "gazedirector/util/error.h"

namespace gazedirector {
namespace fs = std::filesystem;
namespace {

void CheckSize(const fs::path& path, int width, int height) {
  if (width < kMinImageSide || height < kMinImageSide) {
    Fail(ExitCode::kBadInput, "{}: the image is {}x{} pixels; at least {}x{} are needed to hold a face",
         path.string(), width, height, kMinImageSide, kMinImageSide);
  }
  const double megapixels = static_cast<double>(width) * height / 1e6;
  if (megapixels > kMaxImageMegapixels) {
    Fail(ExitCode::kBadInput, "{}: the image is {}x{} ({:.0f} megapixels); at most {:.0f} are supported",
         path.string(), width, height, megapixels, kMaxImageMegapixels);
  }
}

}  // namespace

cv::Mat ToBgr8(const cv::Mat& image) {
  cv::Mat eight_bit;
  switch (image.depth()) {
    case CV_8U: eight_bit = image; break;
    case CV_16U: image.convertTo(eight_bit, CV_8U, 1.0 / 257.0); break;
    case CV_32F:
    case CV_64F: image.convertTo(eight_bit, CV_8U, 255.0); break;
    default: image.convertTo(eight_bit, CV_8U); break;
  }
  cv::Mat bgr;
  switch (eight_bit.channels()) {
    case 1: cv::cvtColor(eight_bit, bgr, cv::COLOR_GRAY2BGR); break;
    case 3: bgr = eight_bit; break;
    case 4: cv::cvtColor(eight_bit, bgr, cv::COLOR_BGRA2BGR); break;
    default: Fail(ExitCode::kBadInput, "unsupported image with {} channels", eight_bit.channels());
  }
  return bgr;
}

cv::Mat ReadImage(const fs::path& path) {
  if (DetectMediaKind(path) != MediaKind::kImage) Fail(ExitCode::kBadInput, "{}: not an image", path.string());
  if (const auto header = ProbeImageHeader(path)) {
    if (!header->complete || header->width <= 0 || header->height <= 0) {
      Fail(ExitCode::kBadInput, "{}: the {} file is truncated or corrupt", path.string(), header->format);
    }
    CheckSize(path, header->width, header->height);
  }
  cv::Mat decoded;
  try {
    decoded = cv::imread(path.string(), cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  } catch (const cv::Exception& e) {
    Fail(ExitCode::kBadInput, "{}: cannot decode the image ({})", path.string(), e.err);
  }
  if (decoded.empty()) Fail(ExitCode::kBadInput, "{}: cannot decode the image (corrupt or unsupported)", path.string());
  CheckSize(path, decoded.cols, decoded.rows);
  return ToBgr8(decoded);
}

void WriteImage(const fs::path& path, const cv::Mat& image, const std::vector<fs::path>& inputs) {
  AtomicOutput output(path, inputs);
  bool written = false;
  try {
    written = cv::imwrite(output.temp_path().string(), image, {cv::IMWRITE_JPEG_QUALITY, 95});
  } catch (const cv::Exception& e) {
    Fail(ExitCode::kOutput, "cannot write {}: {}", path.string(), e.err);
  }
  if (!written) Fail(ExitCode::kOutput, "cannot write {}: unknown image format or unwritable folder", path.string());
  output.Commit();
}

}  // namespace gazedirector
