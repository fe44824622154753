// End-to-end tests of `gazedirector landmarks` on real photos and videos.
#include <algorithm>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;
using testing::DataPath;
using testing::NoPartialFiles;
using testing::Quote;
using testing::ReadText;
using testing::RunCli;
using testing::RunCommand;
using testing::ScratchDir;
using testing::WriteSelectedFrames;

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream stream(text);
  for (std::string line; std::getline(stream, line);) lines.push_back(line);
  return lines;
}

TEST(CliLandmarksTest, WritesJsonCsvAndOverlayForAPortrait) {
  const fs::path dir = ScratchDir("cli_landmarks_image");
  const fs::path input = DataPath("images/d30.jpg");
  const std::string before = ReadText(input);
  std::string output;
  ASSERT_EQ(RunCli("landmarks " + Quote(input) + " -o " + Quote(dir / "out.json") + " --csv " + Quote(dir / "out.csv") +
                       " --overlay " + Quote(dir / "out.png"),
                   &output),
            0)
      << output;
  EXPECT_EQ(ReadText(input), before) << "inputs are never modified";

  const nlohmann::json document = nlohmann::json::parse(ReadText(dir / "out.json"));
  ASSERT_EQ(document["faces"].size(), 1u);
  EXPECT_EQ(document["faces"][0]["landmarks"].size(), 68u);
  EXPECT_EQ(document["camera"]["fx"].get<double>(), 900.0) << "default focal length: the longer image side";

  const std::vector<std::string> csv = Lines(ReadText(dir / "out.csv"));
  ASSERT_EQ(csv.size(), 2u);
  EXPECT_EQ(csv[0].rfind("frame,face_id,timestamp,confidence,success,pose_Tx,pose_Ty,pose_Tz,pose_Rx,pose_Ry,pose_Rz,x_0,", 0), 0u);
  EXPECT_NE(csv[0].find(",y_67"), std::string::npos);
  EXPECT_GT(fs::file_size(dir / "out.png"), 10000u);
  EXPECT_TRUE(NoPartialFiles(dir));
}

TEST(CliLandmarksTest, GivenIntrinsicsAreUsed) {
  const fs::path dir = ScratchDir("cli_landmarks_intrinsics");
  ASSERT_EQ(RunCli("landmarks " + Quote(DataPath("images/s42.jpg")) + " -o " + Quote(dir / "a.json") + " --fx 1500 --cx 250"), 0);
  const nlohmann::json document = nlohmann::json::parse(ReadText(dir / "a.json"));
  EXPECT_EQ(document["camera"]["fx"].get<double>(), 1500.0);
  EXPECT_EQ(document["camera"]["fy"].get<double>(), 1500.0);
  EXPECT_EQ(document["camera"]["cx"].get<double>(), 250.0);
  // A longer focal length puts the same face farther away.
  EXPECT_GT(document["faces"][0]["head_pose"]["translation_mm"][2].get<double>(), 1000.0);
}

// --head-pose kabsch aligns the mean face as the paper does; on a real
// portrait it reads the head as perspective-n-point does, within a degree
// and a little more reprojection error (the paper's minimises the distance
// in space, not in pixels).
TEST(CliLandmarksTest, TheHeadPoseCanBeAlignedByKabsch) {
  const fs::path dir = ScratchDir("cli_landmarks_kabsch");
  const fs::path input = DataPath("images/d30.jpg");
  ASSERT_EQ(RunCli("landmarks " + Quote(input) + " -o " + Quote(dir / "pnp.json")), 0);
  ASSERT_EQ(RunCli("landmarks " + Quote(input) + " -o " + Quote(dir / "kabsch.json") + " --head-pose kabsch"), 0);
  const nlohmann::json pnp = nlohmann::json::parse(ReadText(dir / "pnp.json"))["faces"][0]["head_pose"];
  const nlohmann::json kabsch = nlohmann::json::parse(ReadText(dir / "kabsch.json"))["faces"][0]["head_pose"];
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(kabsch["rotation_xyz_rad"][axis].get<double>(), pnp["rotation_xyz_rad"][axis].get<double>(), 0.02)
        << "axis " << axis;
  }
  EXPECT_NE(kabsch["rotation_xyz_rad"], pnp["rotation_xyz_rad"]) << "another method, other digits";
  EXPECT_GE(kabsch["reprojection_error_px"].get<double>(), pnp["reprojection_error_px"].get<double>());
  EXPECT_LT(kabsch["reprojection_error_px"].get<double>(), 1.1 * pnp["reprojection_error_px"].get<double>());
  std::string output;
  EXPECT_EQ(RunCli("landmarks " + Quote(input) + " -o " + Quote(dir / "x.json") + " --head-pose posit", &output), 2);
  EXPECT_NE(output.find("--head-pose: expected pnp or kabsch, got 'posit'"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(dir / "x.json"));
}

TEST(CliLandmarksTest, ACatIsANoFaceResultWithItsOwnExitCode) {
  const fs::path dir = ScratchDir("cli_landmarks_cat");
  std::string output;
  EXPECT_EQ(RunCli("landmarks " + Quote(DataPath("images/s39.jpg")) + " -o " + Quote(dir / "cat.json"), &output), 3);
  EXPECT_NE(output.find("no face found"), std::string::npos) << output;
  EXPECT_TRUE(nlohmann::json::parse(ReadText(dir / "cat.json"))["faces"].empty());
}

TEST(CliLandmarksTest, BadInputsGetOneLineErrorsAndLeaveNoOutput) {
  const fs::path dir = ScratchDir("cli_landmarks_bad");
  {
    std::ifstream in(DataPath("images/s42.jpg"), std::ios::binary);
    std::string half(20000, '\0');
    in.read(half.data(), static_cast<std::streamsize>(half.size()));
    std::ofstream(dir / "truncated.jpg", std::ios::binary) << half;
    std::ifstream video(DataPath("video/d19.mp4"), std::ios::binary);
    std::string head(200000, '\0');
    video.read(head.data(), static_cast<std::streamsize>(head.size()));
    std::ofstream(dir / "truncated.mp4", std::ios::binary) << head;
    std::ofstream(dir / "empty.png").close();
  }
  ASSERT_EQ(RunCommand("ffmpeg -v error -y -i " + Quote(DataPath("video/d19.mp4")) + " -t 1 -vn -c:a copy " +
                       Quote(dir / "audio_only.mp4")),
            0);
  struct Case {
    std::string arguments;
    int code;
  };
  const std::vector<Case> cases = {
      {"landmarks " + Quote(dir / "missing.jpg") + " -o " + Quote(dir / "o1.json"), 4},
      {"landmarks " + Quote(dir / "truncated.jpg") + " -o " + Quote(dir / "o2.json"), 4},
      {"landmarks " + Quote(dir / "empty.png") + " -o " + Quote(dir / "o3.json"), 4},
      {"landmarks " + Quote(dir / "truncated.mp4") + " -o " + Quote(dir / "o4.jsonl"), 4},
      {"landmarks " + Quote(dir / "audio_only.mp4") + " -o " + Quote(dir / "o9.jsonl"), 4},
      {"landmarks " + Quote(DataPath("images/s42.jpg")), 2},
      {"landmarks " + Quote(DataPath("images/s42.jpg")) + " -o " + Quote(dir / "o5.json") + " --overlay " + Quote(dir / "o5.mp4"), 2},
      {"landmarks " + Quote(DataPath("images/s42.jpg")) + " -o " + Quote(dir / "o6.json") + " --assets " + Quote(dir / "nowhere"), 5},
      {"landmarks " + Quote(DataPath("images/s42.jpg")) + " -o " + Quote(dir / "o7.json") + " --fx inf", 2},
      {"landmarks " + Quote(DataPath("images/s42.jpg")) + " -o " + Quote(dir / "o8.json") + " --cy nan", 2},
  };
  for (const Case& c : cases) {
    std::string output;
    EXPECT_EQ(RunCli(c.arguments, &output), c.code) << c.arguments << "\n" << output;
    EXPECT_FALSE(output.empty());
    EXPECT_EQ(output.find("internal error"), std::string::npos) << output;
    if (c.arguments.find("audio_only") != std::string::npos) {
      EXPECT_NE(output.find("holds no video stream"), std::string::npos) << output;
    }
  }
  for (const char* name :
       {"o1.json", "o2.json", "o3.json", "o4.jsonl", "o5.json", "o6.json", "o7.json", "o8.json", "o9.jsonl"}) {
    EXPECT_FALSE(fs::exists(dir / name)) << name;
  }
  EXPECT_TRUE(NoPartialFiles(dir));
}

// A mistyped command is named, with the ones there are (CLI11 alone said "A subcommand is required").
TEST(CliLandmarksTest, AnUnknownCommandIsNamedWithTheKnownOnes) {
  std::string output;
  EXPECT_EQ(RunCli("landmark " + Quote(DataPath("images/s42.jpg")), &output), 2) << output;
  EXPECT_NE(output.find("gazedirector: error: unknown command 'landmark' (one of redirect, track, landmarks, render, bench, "
                        "eval, train-appearance)"),
            std::string::npos)
      << output;
  EXPECT_EQ(RunCli("eval columbi", &output), 2) << output;
  EXPECT_NE(output.find("unknown eval command 'columbi' (one of landmarks, columbia, redirect-columbia, iris)"),
            std::string::npos)
      << output;
  EXPECT_EQ(RunCli("--version", &output), 0) << output;
}

// Usage errors are one line, as every other error, and say where the
// command's help is (CLI11 printed its message and a second line).
TEST(CliLandmarksTest, UsageErrorsAreOneLineNamingTheCommandsHelp) {
  const struct {
    std::string arguments, message;
  } cases[] = {
      {"landmarks " + Quote(DataPath("images/s42.jpg")),
       "gazedirector: error: --output is required (see gazedirector landmarks --help)\n"},
      {"track " + Quote(DataPath("images/s42.jpg")) + " -o fits.json --eye-patch top",
       "gazedirector: error: --eye-patch: top not in {left,right} (see gazedirector track --help)\n"},
      {"eval columbia --every 0", "(see gazedirector eval columbia --help)\n"},
      {"", "gazedirector: error: no command given: one of redirect, track, landmarks, render, bench, eval, "
           "train-appearance (see gazedirector --help)\n"},
      {"eval --json", "gazedirector: error: no eval command given: one of landmarks, columbia, redirect-columbia, iris "
                      "(see gazedirector eval --help)\n"},
  };
  for (const auto& c : cases) {
    std::string output;
    EXPECT_EQ(RunCli(c.arguments, &output), 2) << c.arguments << "\n" << output;
    EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
    ASSERT_GE(output.size(), c.message.size()) << output;
    EXPECT_EQ(output.substr(output.size() - c.message.size()), c.message) << output;
  }
  std::string help;
  EXPECT_EQ(RunCli("track --help", &help), 0) << help;
  EXPECT_NE(help.find("Usage: gazedirector track [OPTIONS] input"), std::string::npos) << help;
}

TEST(CliLandmarksTest, TracksAVideoFrameByFrameKeepingItsAudio) {
  const fs::path dir = ScratchDir("cli_landmarks_video");
  std::string output;
  ASSERT_EQ(RunCli("landmarks " + Quote(DataPath("video/d19.mp4")) + " -o " + Quote(dir / "d19.jsonl") + " --csv " +
                       Quote(dir / "d19.csv") + " --overlay " + Quote(dir / "d19.mp4") + " --largest",
                   &output),
            0)
      << output;
  const std::vector<std::string> lines = Lines(ReadText(dir / "d19.jsonl"));
  ASSERT_EQ(lines.size(), 250u);
  for (std::size_t i = 0; i < lines.size(); i += 50) {
    const nlohmann::json frame = nlohmann::json::parse(lines[i]);
    EXPECT_EQ(frame["frame"].get<long>(), static_cast<long>(i));
    ASSERT_EQ(frame["faces"].size(), 1u);
    EXPECT_EQ(frame["faces"][0]["face_id"].get<int>(), 0);
  }
  EXPECT_EQ(Lines(ReadText(dir / "d19.csv")).size(), 251u);

  std::string probe;
  RunCommand("ffprobe -v error -count_frames -show_entries stream=codec_type,nb_read_frames -of csv=p=0 " +
                 Quote(dir / "d19.mp4"),
             &probe);
  EXPECT_NE(probe.find("video,250"), std::string::npos) << probe;
  EXPECT_NE(probe.find("audio"), std::string::npos) << probe;
}

// Several inputs go into output folders, each as a run on it alone writes
// it: the second of two copies of a clip gets the same face ids and bytes as
// the first, and a photo's outputs are named after it.
TEST(CliLandmarksTest, SeveralInputsGoIntoFoldersAsEachAlone) {
  const fs::path dir = ScratchDir("cli_landmarks_batch");
  fs::create_directories(dir / "clips");
  ASSERT_EQ(RunCommand("ffmpeg -v error -y -i " + Quote(DataPath("video/d19.mp4")) + " -frames:v 8 -an " +
                       Quote(dir / "clips" / "a.mp4")),
            0);
  fs::copy_file(dir / "clips" / "a.mp4", dir / "clips" / "b.mp4", fs::copy_options::overwrite_existing);
  std::string output;
  ASSERT_EQ(RunCli("landmarks " + Quote(DataPath("images/s12.jpg")) + " " + Quote(dir / "clips") + " -o " +
                       Quote(dir / "fits") + " --csv " + Quote(dir / "csv"),
                   &output),
            0)
      << output;
  EXPECT_NE(output.find("info: [3/3] b.mp4: faces in 8 of 8 frames"), std::string::npos) << output;
  EXPECT_NE(output.find("all 3 inputs done"), std::string::npos) << output;
  const std::string first = ReadText(dir / "fits" / "a.jsonl");
  ASSERT_EQ(Lines(first).size(), 8u);
  EXPECT_EQ(ReadText(dir / "fits" / "b.jsonl"), first);
  EXPECT_EQ(ReadText(dir / "csv" / "b.csv"), ReadText(dir / "csv" / "a.csv"));
  ASSERT_EQ(RunCli("landmarks " + Quote(DataPath("images/s12.jpg")) + " -o " + Quote(dir / "alone.json") + " --csv " +
                       Quote(dir / "alone.csv") + " -q",
                   &output),
            0)
      << output;
  EXPECT_EQ(ReadText(dir / "fits" / "s12.json"), ReadText(dir / "alone.json"));
  EXPECT_EQ(ReadText(dir / "csv" / "s12.csv"), ReadText(dir / "alone.csv"));
  // Outputs named as files where folders are meant are refused before any work.
  EXPECT_EQ(RunCli("landmarks " + Quote(dir / "clips") + " -o " + Quote(dir / "never") + " --csv " + Quote(dir / "all.csv"),
                   &output),
            2)
      << output;
  EXPECT_NE(output.find("--csv " + (dir / "all.csv").string() + ": several inputs are written into a folder"),
            std::string::npos)
      << output;
  EXPECT_FALSE(fs::exists(dir / "never"));
}

// A folder's subfolders are read only with --recursive, and their outputs go
// into subfolders of the same names; an output folder inside the input folder
// is not read back as input.
TEST(CliLandmarksTest, RecursiveFoldersKeepTheirSubfoldersInTheOutputs) {
  const fs::path dir = ScratchDir("cli_landmarks_recursive");
  fs::create_directories(dir / "album" / "2024");
  fs::copy_file(DataPath("images/s12.jpg"), dir / "album" / "s12.jpg", fs::copy_options::overwrite_existing);
  fs::copy_file(DataPath("images/s12.jpg"), dir / "album" / "2024" / "s12.jpg", fs::copy_options::overwrite_existing);
  std::string output;
  ASSERT_EQ(RunCli("landmarks " + Quote(dir / "album") + " -o " + Quote(dir / "flat"), &output), 0) << output;
  EXPECT_NE(output.find("1 image(s) or video(s) in its subfolders left out; --recursive reads them"), std::string::npos)
      << output;
  EXPECT_FALSE(fs::exists(dir / "flat" / "2024"));

  // The second run finds the first one's outputs inside the album, its overlays photos too.
  for (int run = 0; run < 2; ++run) {
    ASSERT_EQ(RunCli("landmarks -r " + Quote(dir / "album") + "/ -o " + Quote(dir / "album" / "fits") + " --csv " +
                         Quote(dir / "album" / "csv") + " --overlay " + Quote(dir / "album" / "overlay"),
                     &output),
              0)
        << output;
    EXPECT_NE(output.find("info: [1/2] 2024/s12.jpg: 1 face -> "), std::string::npos) << output;
    EXPECT_NE(output.find("all 2 inputs done"), std::string::npos) << output;
  }
  const nlohmann::json nested = nlohmann::json::parse(ReadText(dir / "album" / "fits" / "2024" / "s12.json"));
  EXPECT_EQ(nested["input"], (dir / "album" / "2024" / "s12.jpg").string());
  EXPECT_EQ(nested["faces"], nlohmann::json::parse(ReadText(dir / "flat" / "s12.json"))["faces"]);
  EXPECT_EQ(ReadText(dir / "album" / "csv" / "2024" / "s12.csv"), ReadText(dir / "album" / "csv" / "s12.csv"));
  EXPECT_TRUE(fs::exists(dir / "album" / "overlay" / "2024" / "s12.jpg"));

  fs::remove(dir / "album" / "s12.jpg");
  EXPECT_EQ(RunCli("landmarks " + Quote(dir / "album") + " -o " + Quote(dir / "never"), &output), 4) << output;
  EXPECT_NE(output.find("the folder holds no images or videos, but its subfolders hold 3 (--recursive reads them)"),
            std::string::npos)
      << output;
  EXPECT_FALSE(fs::exists(dir / "never"));
}

// A variable-rate video (as phones and screen recorders write) keeps each
// frame's time in the fits and in the overlay, which holds frames over the
// sparse stretches instead of squeezing all frames to the average rate.
TEST(CliLandmarksTest, AVariableRateVideosFramesKeepTheirTimes) {
  const fs::path dir = ScratchDir("cli_landmarks_vfr");
  // d19 at 30 fps: every 3rd frame of the first second, all of the second, every 3rd of the third.
  ASSERT_EQ(WriteSelectedFrames("video/d19.mp4", 3, "not(mod(n,3))+between(n,30,59)", dir / "vfr.mp4", true), 0);
  std::string output;
  ASSERT_EQ(RunCli("landmarks " + Quote(dir / "vfr.mp4") + " -o " + Quote(dir / "vfr.jsonl") + " --overlay " +
                       Quote(dir / "overlay.mp4"),
                   &output),
            0)
      << output;
  const std::vector<std::string> lines = Lines(ReadText(dir / "vfr.jsonl"));
  ASSERT_EQ(lines.size(), 50u);
  EXPECT_NEAR(nlohmann::json::parse(lines[9])["timestamp"].get<double>(), 0.9, 1e-3);
  EXPECT_NEAR(nlohmann::json::parse(lines[11])["timestamp"].get<double>(), 31 / 30.0, 1e-3);
  EXPECT_NEAR(nlohmann::json::parse(lines[49])["timestamp"].get<double>(), 87 / 30.0, 1e-3);

  std::string probe;
  RunCommand("ffprobe -v error -count_frames -show_entries stream=codec_type,r_frame_rate,nb_read_frames -of csv=p=0 " +
                 Quote(dir / "overlay.mp4"),
             &probe);
  EXPECT_NE(probe.find("video,30/1,88"), std::string::npos) << probe;  // source frames 0 to 87 at 30 fps
  EXPECT_NE(probe.find("audio"), std::string::npos) << probe;
}

// A portrait saved a quarter turned (a phone held sideways, nothing in the
// file to say so) is found, and its box is reported turned with it.
TEST(CliLandmarksTest, ReportsATiltedFaceWithItsTurnedBox) {
  const fs::path dir = ScratchDir("cli_landmarks_tilted");
  cv::Mat turned;
  cv::rotate(cv::imread(DataPath("images/s42.jpg").string()), turned, cv::ROTATE_90_COUNTERCLOCKWISE);
  ASSERT_TRUE(cv::imwrite((dir / "turned.png").string(), turned));
  std::string output;
  ASSERT_EQ(RunCli("landmarks " + Quote(dir / "turned.png") + " -o " + Quote(dir / "out.json"), &output), 0) << output;
  const nlohmann::json document = nlohmann::json::parse(ReadText(dir / "out.json"));
  ASSERT_EQ(document["faces"].size(), 1u);
  // Counter-clockwise as shown is a negative roll; s42's own tilt is a few degrees.
  EXPECT_NEAR(document["faces"][0]["box_roll_deg"].get<double>(), -90.0, 10.0);
  EXPECT_GT(document["faces"][0]["confidence"].get<double>(), 0.9);
}

// `eval landmarks --turn` prints one row per turn; --json gives them under
// by_turn, while the plain evaluation keeps its flat object.
TEST(CliLandmarksTest, EvalLandmarksReportsEachTurn) {
  std::string output;
  ASSERT_EQ(RunCli("eval landmarks --turn 0 90 --json", &output), 0) << output;
  const nlohmann::json result = nlohmann::json::parse(Lines(output).back());
  ASSERT_EQ(result["by_turn"].size(), 2u);
  for (const nlohmann::json& row : result["by_turn"]) {
    EXPECT_EQ(row["faces"].get<int>(), 25);
    EXPECT_GE(row["detected"].get<int>(), 24) << row.dump();
    EXPECT_LT(row["mean_error_pipeline"].get<double>(), 0.03) << row.dump();
  }
  EXPECT_EQ(result["by_turn"][1]["turn_deg"].get<double>(), 90.0);
  ASSERT_EQ(RunCli("eval landmarks --json", &output), 0) << output;
  EXPECT_TRUE(nlohmann::json::parse(Lines(output).back()).contains("mean_error_pipeline"));
}

}  // namespace
}  // namespace gazedirector
