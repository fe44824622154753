#include "gazedirector/io/media.h"

#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;
using testing::DataPath;
using testing::ScratchDir;
using testing::WritePrefix;

ExitCode DetectError(const fs::path& path) {
  return testing::ExitCodeOf([&] { DetectMediaKind(path); });
}

// The file's first bytes decide; the extension only where they say nothing.
TEST(MediaTest, TellsImagesFromVideosByTheirBytes) {
  const fs::path dir = ScratchDir("media_kind");
  EXPECT_EQ(DetectMediaKind(DataPath("images/s42.jpg")), MediaKind::kImage);
  EXPECT_EQ(DetectMediaKind(DataPath("video/d3.mp4")), MediaKind::kVideo);
  fs::copy_file(DataPath("images/s42.jpg"), dir / "photo.mp4", fs::copy_options::overwrite_existing);
  EXPECT_EQ(DetectMediaKind(dir / "photo.mp4"), MediaKind::kImage);
  fs::copy_file(DataPath("video/d3.mp4"), dir / "clip.jpg", fs::copy_options::overwrite_existing);
  EXPECT_EQ(DetectMediaKind(dir / "clip.jpg"), MediaKind::kVideo);
  ASSERT_TRUE(cv::imwrite((dir / "still.png").string(), cv::imread(DataPath("images/s42.jpg").string())));
  EXPECT_EQ(DetectMediaKind(dir / "still.png"), MediaKind::kImage);
  // Unknown bytes under a known extension: the decoder will say what is wrong.
  std::ofstream(dir / "text.png") << "not an image at all";
  EXPECT_EQ(DetectMediaKind(dir / "text.png"), MediaKind::kImage);
  std::ofstream(dir / "text.MOV") << "not a video at all";
  EXPECT_EQ(DetectMediaKind(dir / "text.MOV"), MediaKind::kVideo);

  std::ofstream(dir / "notes.txt") << "neither";
  EXPECT_EQ(DetectError(dir / "notes.txt"), ExitCode::kBadInput);
  std::ofstream(dir / "empty.jpg").close();
  EXPECT_EQ(DetectError(dir / "empty.jpg"), ExitCode::kBadInput);
  EXPECT_EQ(DetectError(dir / "missing.mp4"), ExitCode::kBadInput);
  fs::create_directories(dir / "folder.mp4");
  EXPECT_EQ(DetectError(dir / "folder.mp4"), ExitCode::kBadInput);
}

TEST(MediaTest, ExtensionsIgnoreCase) {
  EXPECT_EQ(LowerExtension("photo.JPG"), ".jpg");
  EXPECT_EQ(LowerExtension("dir.v2/archive.tar.GZ"), ".gz");
  EXPECT_EQ(LowerExtension("README"), "");
  EXPECT_TRUE(HasVideoExtension("clip.MP4"));
  EXPECT_TRUE(HasVideoExtension("loop.gif"));
  EXPECT_FALSE(HasVideoExtension("photo.png"));
  EXPECT_FALSE(HasVideoExtension("mp4"));
}

// A folder's images and videos, in name order: not its other files, hidden
// files or subfolders, whatever their names say.
TEST(MediaTest, ListsAFoldersImagesAndVideosByName) {
  const fs::path dir = ScratchDir("media_folder");
  for (const char* name : {"b.JPG", "a.mp4", "c.png", "notes.txt", ".hidden.jpg", "fits.jsonl", "Z.webm"}) {
    std::ofstream(dir / name) << "x";
  }
  fs::create_directories(dir / "sub.jpg");
  std::ofstream(dir / "sub.jpg" / "d.jpg") << "x";
  const std::vector<fs::path> expected = {dir / "Z.webm", dir / "a.mp4", dir / "b.JPG", dir / "c.png"};
  EXPECT_EQ(MediaFilesIn(dir), expected);
  EXPECT_TRUE(MediaFilesIn(dir / "sub.jpg").size() == 1);
  EXPECT_EQ(testing::ExitCodeOf([&] { MediaFilesIn(dir / "missing"); }), ExitCode::kBadInput);
  EXPECT_TRUE(HasImageExtension("photo.TIFF"));
  EXPECT_FALSE(HasImageExtension("clip.mp4"));
}

// Recursively, a folder's subfolders are listed too, by path, but not hidden
// ones or those skipped (a batch's outputs inside it).
TEST(MediaTest, ListsSubfoldersRecursivelyExceptHiddenAndSkippedOnes) {
  const fs::path dir = ScratchDir("media_folder_recursive");
  for (const char* folder : {"2024/trip", ".thumbnails", "out", "empty"}) fs::create_directories(dir / folder);
  for (const char* name : {"b.jpg", "2024/a.png", "2024/notes.txt", "2024/trip/c.mp4", ".thumbnails/t.jpg", "out/b.jpg"}) {
    std::ofstream(dir / name) << "x";
  }
  const std::vector<fs::path> all = {dir / "2024/a.png", dir / "2024/trip/c.mp4", dir / "b.jpg", dir / "out/b.jpg"};
  EXPECT_EQ(MediaFilesIn(dir, true), all);
  const std::vector<fs::path> without_out = {dir / "2024/a.png", dir / "2024/trip/c.mp4", dir / "b.jpg"};
  EXPECT_EQ(MediaFilesIn(dir, true, {dir / "out", dir / "missing"}), without_out);
  EXPECT_EQ(MediaFilesIn(dir), std::vector<fs::path>{dir / "b.jpg"});
}

// The header's size is the decoded image's, read without decoding; a file cut
// short is told from a whole one.
TEST(MediaTest, ProbesJpegAndPngHeadersWithoutDecoding) {
  const fs::path dir = ScratchDir("media_probe");
  for (const char* name : {"d19.jpg", "d30.jpg", "d8.jpg", "s12.jpg", "s39.jpg", "s42.jpg"}) {
    const fs::path jpeg = DataPath(std::string("images/") + name);
    const cv::Mat decoded = cv::imread(jpeg.string(), cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION);
    ASSERT_FALSE(decoded.empty()) << name;
    const auto header = ProbeImageHeader(jpeg);
    ASSERT_TRUE(header.has_value()) << name;
    EXPECT_EQ(header->format, "jpeg");
    EXPECT_EQ(header->width, decoded.cols) << name;
    EXPECT_EQ(header->height, decoded.rows) << name;
    EXPECT_TRUE(header->complete) << name;

    WritePrefix(jpeg, dir / "cut.jpg", fs::file_size(jpeg) / 2);
    const auto cut = ProbeImageHeader(dir / "cut.jpg");
    ASSERT_TRUE(cut.has_value()) << name;
    EXPECT_EQ(cut->width, decoded.cols) << name;
    EXPECT_FALSE(cut->complete) << name;
  }

  const fs::path png = dir / "whole.png";
  const cv::Mat image = cv::imread(DataPath("images/d30.jpg").string());
  ASSERT_TRUE(cv::imwrite(png.string(), image));
  const auto header = ProbeImageHeader(png);
  ASSERT_TRUE(header.has_value());
  EXPECT_EQ(header->format, "png");
  EXPECT_EQ(header->width, image.cols);
  EXPECT_EQ(header->height, image.rows);
  EXPECT_TRUE(header->complete);
  WritePrefix(png, dir / "cut.png", fs::file_size(png) - 100);
  EXPECT_FALSE(ProbeImageHeader(dir / "cut.png")->complete);
  WritePrefix(png, dir / "stub.png", 16);  // the signature, not the size
  EXPECT_FALSE(ProbeImageHeader(dir / "stub.png")->complete);

  EXPECT_FALSE(ProbeImageHeader(DataPath("video/d3.mp4")).has_value());
  WritePrefix(png, dir / "tiny.png", 4);
  EXPECT_FALSE(ProbeImageHeader(dir / "tiny.png").has_value());
  EXPECT_FALSE(ProbeImageHeader(dir / "missing.png").has_value());
}

}  // namespace
}  // namespace gazedirector
