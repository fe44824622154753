#include "gazedirector/io/image_io.h"

#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

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

bool HoldsSixteenBits(const fs::path& path) {
  const std::string extension = LowerExtension(path);
  return extension == ".png" || extension == ".tif" || extension == ".tiff";
}

bool MayHoldAlpha(const fs::path& path) { return HoldsSixteenBits(path) || LowerExtension(path) == ".webp"; }

// The image scaled to 8 bits, its channels kept (shared, not copied, when it is 8-bit already).
cv::Mat To8Bit(const cv::Mat& image) {
  cv::Mat eight_bit;
  switch (image.depth()) {
    case CV_8U: eight_bit = image; break;
    case CV_16U: image.convertTo(eight_bit, CV_8U, 1.0 / 257.0); break;
    case CV_32F:
    case CV_64F: image.convertTo(eight_bit, CV_8U, 255.0); break;
    default: image.convertTo(eight_bit, CV_8U); break;
  }
  return eight_bit;
}

}  // namespace

cv::Mat ToBgr8(const cv::Mat& image) {
  const cv::Mat eight_bit = To8Bit(image);
  cv::Mat bgr;
  switch (eight_bit.channels()) {
    case 1: cv::cvtColor(eight_bit, bgr, cv::COLOR_GRAY2BGR); break;
    case 3: bgr = eight_bit; break;
    case 4: cv::cvtColor(eight_bit, bgr, cv::COLOR_BGRA2BGR); break;
    default: Fail(ExitCode::kBadInput, "unsupported image with {} channels", eight_bit.channels());
  }
  return bgr;
}

namespace {

// The image as OpenCV decodes it with the EXIF orientation applied (alpha dropped).
cv::Mat Decode(const fs::path& path) {
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
  return decoded;
}

}  // namespace

cv::Mat ReadImage(const fs::path& path) { return ToBgr8(Decode(path)); }

SourceImage ReadSourceImage(const fs::path& path) {
  cv::Mat decoded = Decode(path);
  cv::Mat bgr = ToBgr8(decoded);
  // OpenCV keeps alpha only when it also ignores the EXIF orientation; that
  // decoding is the original when it shows the same picture.
  cv::Mat unchanged;
  if (MayHoldAlpha(path)) {
    try {
      unchanged = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception&) {
      // The picture is decoded already; without this decoding it only loses its alpha.
    }
  }
  if (unchanged.channels() == 4 && unchanged.size() == bgr.size() &&
      cv::norm(ToBgr8(unchanged), bgr, cv::NORM_INF) == 0) {
    decoded = unchanged;
  }
  return {std::move(decoded), std::move(bgr)};
}

cv::Mat InSourceFormat(const SourceImage& source, const cv::Mat& edited, const fs::path& output) {
  const cv::Mat& original = source.original;
  const bool deep = original.depth() == CV_16U && HoldsSixteenBits(output);
  const bool alpha = original.channels() == 4 && MayHoldAlpha(output);
  // Where the output holds only 8-bit colour, that is what the edit is.
  if (!deep && !alpha && original.channels() != 1) return edited;

  // The original in the format the output can hold; the edit goes over it where it changed anything.
  // (Past the return above, four channels always keep their alpha: a format that holds 16 bits holds alpha too.)
  cv::Mat base = (deep ? original : To8Bit(original)).clone();
  cv::Mat difference, unchanged;
  cv::absdiff(edited, source.bgr, difference);
  cv::inRange(difference, cv::Scalar::all(0), cv::Scalar::all(0), unchanged);  // every channel equal

  cv::Mat overlay = edited;
  if (base.channels() == 1) cv::cvtColor(edited, overlay, cv::COLOR_BGR2GRAY);
  if (base.depth() == CV_16U) overlay.convertTo(overlay, CV_16U, 257.0);
  if (base.channels() == 4) {
    std::vector<cv::Mat> planes;
    cv::split(overlay, planes);
    planes.emplace_back();
    cv::extractChannel(base, planes.back(), 3);
    cv::merge(planes, overlay);
  }
  overlay.copyTo(base, unchanged == 0);
  return base;
}

void WriteImage(const fs::path& path, const cv::Mat& image, const std::vector<fs::path>& inputs) {
  WriteImage(path, image, PhotoMetadata(), inputs);
}

void WriteImage(const fs::path& path, const cv::Mat& image, const PhotoMetadata& metadata,
                const std::vector<fs::path>& inputs) {
  AtomicOutput output(path, inputs);
  bool written = false;
  try {
    written = cv::imwrite(output.temp_path().string(), image, {cv::IMWRITE_JPEG_QUALITY, 95});
  } catch (const cv::Exception& e) {
    Fail(ExitCode::kOutput, "cannot write {}: {}", path.string(), e.err);
  }
  if (!written) Fail(ExitCode::kOutput, "cannot write {}: unknown image format or unwritable folder", path.string());
  if (!metadata.WriteTo(output.temp_path(), image.cols, image.rows)) {
    spdlog::warn("{}: written without the source photo's metadata (EXIF, ICC profile), which could not be carried "
                 "into a {} file",
                 path.string(), LowerExtension(path));
  }
  output.Commit();
}

}  // namespace gazedirector
