// End-to-end tests of `gazedirector render`: the eye-region model alone and
// over a real face.
#include <array>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "gazedirector/io/image_io.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;
using testing::DataPath;
using testing::NoPartialFiles;
using testing::Quote;
using testing::RunCli;
using testing::ScratchDir;

// The colours `render --buffers` gives each part in parts.png: the two skin
// regions, then the two eyeballs.
const std::array<cv::Vec3b, 4> kPartColours = {cv::Vec3b(60, 160, 230), cv::Vec3b(60, 230, 160),
                                               cv::Vec3b(230, 120, 60), cv::Vec3b(230, 60, 200)};

// The mean x of the darkest third of the eyeballs' pixels (their irises and
// pupils), from a render and its buffers.
double IrisX(const fs::path& render, const fs::path& buffers) {
  const cv::Mat parts = ReadImage(buffers / "parts.png");
  cv::Mat eyeballs, second;
  cv::inRange(parts, kPartColours[2], kPartColours[2], eyeballs);
  cv::inRange(parts, kPartColours[3], kPartColours[3], second);
  eyeballs |= second;
  cv::Mat gray;
  cv::cvtColor(ReadImage(render), gray, cv::COLOR_BGR2GRAY);
  std::vector<std::pair<int, int>> pixels;  // (grey, x)
  for (int y = 0; y < gray.rows; ++y) {
    for (int x = 0; x < gray.cols; ++x) {
      if (eyeballs.at<uchar>(y, x) > 0) pixels.emplace_back(gray.at<uchar>(y, x), x);
    }
  }
  std::sort(pixels.begin(), pixels.end());
  const std::size_t third = std::max<std::size_t>(1, pixels.size() / 3);
  double sum = 0;
  for (std::size_t i = 0; i < third; ++i) sum += pixels[i].second;
  return sum / third;
}

TEST(CliRenderTest, RendersTheModelAloneWithItsBuffersAndTurnsItsEyes) {
  const fs::path dir = ScratchDir("cli_render_alone");
  std::string output;
  ASSERT_EQ(RunCli("render -o " + Quote(dir / "ahead.png") + " --size 320x160 --buffers " + Quote(dir / "buffers"),
                   &output),
            0)
      << output;
  const cv::Mat ahead = ReadImage(dir / "ahead.png");
  EXPECT_EQ(ahead.size(), cv::Size(320, 160));
  const cv::Mat mask = cv::imread((dir / "buffers" / "mask.png").string(), cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(mask.size(), ahead.size());
  // Both eye regions fill much of the frame, and nothing is drawn outside them.
  const double covered = static_cast<double>(cv::countNonZero(mask)) / mask.total();
  EXPECT_GT(covered, 0.2);
  EXPECT_LT(covered, 0.95);
  cv::Mat gray;
  cv::cvtColor(ahead, gray, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(cv::countNonZero(gray & ~mask), 0);
  // The part ids: the two skin regions and the two eyeballs each show.
  const cv::Mat parts = ReadImage(dir / "buffers" / "parts.png");
  for (const cv::Vec3b& colour : kPartColours) {
    cv::Mat match;
    cv::inRange(parts, colour, colour, match);
    EXPECT_GT(cv::countNonZero(match), 100) << colour;
  }
  // Gaze in the head's frame: toward the subject's left (+ yaw) is the image's right for a face
  // that faces the camera, so the irises move right (7 to 9 px here).
  const struct {
    std::string name;
    int yaw;
  } turns[] = {{"left", 20}, {"right", -20}};
  for (const auto& turn : turns) {
    ASSERT_EQ(RunCli(fmt::format("render -o {} --size 320x160 --gaze 0,{} --buffers {}", Quote(dir / (turn.name + ".png")),
                                 turn.yaw, Quote(dir / turn.name)),
                     &output),
              0)
        << output;
  }
  const double ahead_x = IrisX(dir / "ahead.png", dir / "buffers");
  EXPECT_GT(IrisX(dir / "left.png", dir / "left"), ahead_x + 5);
  EXPECT_LT(IrisX(dir / "right.png", dir / "right"), ahead_x - 5);
  EXPECT_TRUE(NoPartialFiles(dir));
}

TEST(CliRenderTest, DrawsTheModelOverARealFaceAndNothingElse) {
  const fs::path dir = ScratchDir("cli_render_overlay");
  const fs::path photo = DataPath("images/d30.jpg");
  std::string output;
  ASSERT_EQ(RunCli("render -o " + Quote(dir / "over.png") + " --overlay " + Quote(photo), &output), 0) << output;
  const cv::Mat original = ReadImage(photo), over = ReadImage(dir / "over.png");
  ASSERT_EQ(over.size(), original.size());
  cv::Mat difference, changed;
  cv::absdiff(original, over, difference);
  cv::cvtColor(difference, changed, cv::COLOR_BGR2GRAY);
  // The model covers the two eye regions: a small share of a portrait.
  const double share = static_cast<double>(cv::countNonZero(changed)) / changed.total();
  EXPECT_GT(share, 0.005);
  EXPECT_LT(share, 0.15);
  // Placed on the eyes: the changed pixels' centre lies in the photo's middle columns, above its lowest quarter.
  const cv::Rect drawn = cv::boundingRect(changed);
  const cv::Point centre = (drawn.tl() + drawn.br()) / 2;
  EXPECT_GT(centre.x, original.cols / 4);
  EXPECT_LT(centre.x, 3 * original.cols / 4);
  EXPECT_LT(centre.y, 3 * original.rows / 4);
}

TEST(CliRenderTest, BadSizesAndClashingOptionsFailWithUsageErrors) {
  const fs::path dir = ScratchDir("cli_render_errors");
  std::string output;
  EXPECT_EQ(RunCli("render -o " + Quote(dir / "a.png") + " --size 10x10", &output), 2);
  EXPECT_NE(output.find("--size 10x10: expected WIDTHxHEIGHT between 16 and 8192"), std::string::npos) << output;
  // Over a photo the image is the photo's size, so --size would be ignored.
  EXPECT_EQ(RunCli("render -o " + Quote(dir / "b.png") + " --size 320x160 --overlay " +
                       Quote(DataPath("images/d30.jpg")),
                   &output),
            2);
  EXPECT_NE(output.find("--size excludes --overlay"), std::string::npos) << output;
  EXPECT_EQ(RunCli("render -o " + Quote(dir / "c.mp4"), &output), 2) << output;
  EXPECT_NE(output.find("-o " + (dir / "c.mp4").string() +
                        ": expected an image file (.png, .jpg, .jpeg, .tif, .tiff, .webp, .bmp)"),
            std::string::npos)
      << output;
  EXPECT_TRUE(fs::is_empty(dir));
}

}  // namespace
}  // namespace gazedirector
