#include "gazedirector/io/image_io.h"

#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "gazedirector/io/media.h"
#include "gazedirector/util/error.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;
using testing::DataPath;
using testing::ScratchDir;

ExitCode ReadError(const fs::path& path) {
  return testing::ExitCodeOf([&] { ReadImage(path); });
}

TEST(ImageIoTest, ReadsRealPhotoAsBgr8) {
  const cv::Mat image = ReadImage(DataPath("images/s42.jpg"));
  EXPECT_EQ(image.type(), CV_8UC3);
  EXPECT_EQ(image.cols, 512);
  EXPECT_EQ(image.rows, 512);
}

TEST(ImageIoTest, ConvertsGraySixteenBitAndAlpha) {
  const fs::path dir = ScratchDir("image_io_formats");
  const cv::Mat photo = cv::imread(DataPath("images/d19.jpg").string());
  cv::Mat gray, deep, alpha;
  cv::cvtColor(photo, gray, cv::COLOR_BGR2GRAY);
  photo.convertTo(deep, CV_16U, 257.0);
  cv::cvtColor(photo, alpha, cv::COLOR_BGR2BGRA);
  ASSERT_TRUE(cv::imwrite((dir / "gray.png").string(), gray));
  ASSERT_TRUE(cv::imwrite((dir / "deep.png").string(), deep));
  ASSERT_TRUE(cv::imwrite((dir / "alpha.png").string(), alpha));

  const cv::Mat from_gray = ReadImage(dir / "gray.png");
  ASSERT_EQ(from_gray.type(), CV_8UC3);
  cv::Mat channels[3];
  cv::split(from_gray, channels);
  EXPECT_EQ(cv::norm(channels[0], gray, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(channels[2], gray, cv::NORM_INF), 0);

  const cv::Mat from_deep = ReadImage(dir / "deep.png");
  ASSERT_EQ(from_deep.type(), CV_8UC3);
  EXPECT_LE(cv::norm(from_deep, photo, cv::NORM_INF), 1);

  const cv::Mat from_alpha = ReadImage(dir / "alpha.png");
  ASSERT_EQ(from_alpha.type(), CV_8UC3);
  EXPECT_EQ(cv::norm(from_alpha, photo, cv::NORM_INF), 0);
}

// A real photo edited as a redirection would: a patch around one eye changed.
cv::Mat EditedEye(const cv::Mat& bgr) {
  cv::Mat edited = bgr.clone();
  cv::Mat patch = edited(cv::Rect(200, 180, 40, 20));
  patch.forEach<cv::Vec3b>([](cv::Vec3b& pixel, const int*) { pixel = cv::Vec3b(pixel[1], pixel[2], pixel[0]); });
  edited.at<cv::Vec3b>(300, 300)[0] ^= 1;  // the smallest change counts too
  return edited;
}

TEST(ImageIoTest, AnEditKeepsTheSourcesDepthAlphaAndUntouchedPixels) {
  const fs::path dir = ScratchDir("image_io_source_format");
  const cv::Mat photo = cv::imread(DataPath("images/d19.jpg").string());
  // 16 bits with low bits of its own, and a real alpha gradient.
  cv::Mat deep;
  photo.convertTo(deep, CV_16U, 257.0);
  deep += cv::Scalar::all(77);
  cv::Mat alpha(photo.size(), CV_16U);
  for (int y = 0; y < alpha.rows; ++y) alpha.row(y).setTo(cv::Scalar(65535 - y * 40));
  std::vector<cv::Mat> planes;
  cv::split(deep, planes);
  planes.push_back(alpha);
  cv::Mat deep_alpha;
  cv::merge(planes, deep_alpha);
  ASSERT_TRUE(cv::imwrite((dir / "deep_alpha.png").string(), deep_alpha));

  const SourceImage source = ReadSourceImage(dir / "deep_alpha.png");
  ASSERT_EQ(source.original.type(), CV_16UC4);
  ASSERT_EQ(source.bgr.type(), CV_8UC3);
  const cv::Mat edited = EditedEye(source.bgr);

  const cv::Mat as_png = InSourceFormat(source, edited, dir / "out.png");
  ASSERT_EQ(as_png.type(), CV_16UC4);
  cv::Mat edited_alpha_less, original_alpha_less;
  cv::cvtColor(as_png, edited_alpha_less, cv::COLOR_BGRA2BGR);
  cv::cvtColor(source.original, original_alpha_less, cv::COLOR_BGRA2BGR);
  cv::Mat out_alpha;
  cv::extractChannel(as_png, out_alpha, 3);
  EXPECT_EQ(cv::norm(out_alpha, alpha, cv::NORM_INF), 0) << "the alpha is the source's";
  cv::Mat unchanged_mask(photo.size(), CV_8U, cv::Scalar(255));
  unchanged_mask(cv::Rect(200, 180, 40, 20)).setTo(0);
  unchanged_mask.at<uchar>(300, 300) = 0;
  EXPECT_EQ(cv::norm(edited_alpha_less, original_alpha_less, cv::NORM_INF, unchanged_mask), 0)
      << "untouched pixels keep all 16 bits";
  cv::Mat edited_deep;
  edited.convertTo(edited_deep, CV_16U, 257.0);
  EXPECT_EQ(cv::norm(edited_alpha_less(cv::Rect(200, 180, 40, 20)), edited_deep(cv::Rect(200, 180, 40, 20)), cv::NORM_INF), 0);
  EXPECT_EQ(edited_alpha_less.at<cv::Vec3w>(300, 300)[0], edited.at<cv::Vec3b>(300, 300)[0] * 257);

  // JPEG holds neither 16 bits nor alpha: the edit as it is.
  const cv::Mat as_jpeg = InSourceFormat(source, edited, dir / "out.jpg");
  EXPECT_EQ(as_jpeg.type(), CV_8UC3);
  EXPECT_EQ(cv::norm(as_jpeg, edited, cv::NORM_INF), 0);

  // A grayscale photo stays grayscale.
  cv::Mat gray;
  cv::cvtColor(photo, gray, cv::COLOR_BGR2GRAY);
  ASSERT_TRUE(cv::imwrite((dir / "gray.png").string(), gray));
  const SourceImage gray_source = ReadSourceImage(dir / "gray.png");
  const cv::Mat gray_out = InSourceFormat(gray_source, EditedEye(gray_source.bgr), dir / "out.png");
  EXPECT_EQ(gray_out.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(gray_out, gray, cv::NORM_INF, unchanged_mask), 0);
}

TEST(ImageIoTest, RefusesMissingEmptyTinyAndTruncatedImages) {
  const fs::path dir = ScratchDir("image_io_bad");
  EXPECT_EQ(ReadError(dir / "missing.jpg"), ExitCode::kBadInput);

  std::ofstream(dir / "empty.jpg").close();
  EXPECT_EQ(ReadError(dir / "empty.jpg"), ExitCode::kBadInput);

  ASSERT_TRUE(cv::imwrite((dir / "one.png").string(), cv::Mat(1, 1, CV_8UC3, cv::Scalar(1, 2, 3))));
  EXPECT_EQ(ReadError(dir / "one.png"), ExitCode::kBadInput);

  const fs::path jpeg = DataPath("images/d30.jpg");
  testing::WritePrefix(jpeg, dir / "cut.jpg", fs::file_size(jpeg) / 2);
  EXPECT_EQ(ReadError(dir / "cut.jpg"), ExitCode::kBadInput);

  const fs::path png = dir / "whole.png";
  ASSERT_TRUE(cv::imwrite(png.string(), cv::imread(jpeg.string())));
  testing::WritePrefix(png, dir / "cut.png", fs::file_size(png) - 100);
  EXPECT_EQ(ReadError(dir / "cut.png"), ExitCode::kBadInput);

  std::ofstream(dir / "text.jpg") << "not an image at all";
  EXPECT_EQ(ReadError(dir / "text.jpg"), ExitCode::kBadInput);
}

TEST(ImageIoTest, RefusesHugeImagesBeforeDecoding) {
  // A real PNG of 100000 x 100000 would take 30 GB to decode; its header is
  // enough to refuse it. Build one from a real PNG by patching IHDR's size
  // (the checksum is wrong, which the header probe does not look at).
  const fs::path dir = ScratchDir("image_io_huge");
  const fs::path png = dir / "small.png";
  ASSERT_TRUE(cv::imwrite(png.string(), cv::imread(DataPath("images/s42.jpg").string())));
  std::fstream file(png, std::ios::in | std::ios::out | std::ios::binary);
  const unsigned char size[8] = {0x00, 0x01, 0x86, 0xA0, 0x00, 0x01, 0x86, 0xA0};
  file.seekp(16);
  file.write(reinterpret_cast<const char*>(size), 8);
  file.close();
  const auto header = ProbeImageHeader(png);
  ASSERT_TRUE(header.has_value());
  EXPECT_EQ(header->width, 100000);
  EXPECT_EQ(ReadError(png), ExitCode::kBadInput);
}

TEST(ImageIoTest, WritesAtomicallyAndNeverOverAnInput) {
  const fs::path dir = ScratchDir("image_io_write");
  const cv::Mat image = ReadImage(DataPath("images/s42.jpg"));
  WriteImage(dir / "sub" / "copy.png", image);
  EXPECT_TRUE(fs::is_regular_file(dir / "sub" / "copy.png"));
  for (const auto& entry : fs::directory_iterator(dir / "sub")) {
    EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos);
  }
  const fs::path input = dir / "input.png";
  fs::copy_file(dir / "sub" / "copy.png", input);
  const auto size_before = fs::file_size(input);
  EXPECT_THROW(WriteImage(input, image, {input}), Error);
  EXPECT_EQ(fs::file_size(input), size_before);
  EXPECT_THROW(WriteImage(dir / "unknown.format", image), Error);
  EXPECT_FALSE(fs::exists(dir / "unknown.format"));
}

}  // namespace
}  // namespace gazedirector
