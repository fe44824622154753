// End-to-end tests of `gazedirector track` and `gazedirector redirect` on real photos and videos.
#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "gazedirector/io/image_io.h"
#include "gazedirector/io/video_reader.h"
#include "gazedirector/util/statistics.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;
using testing::CliPath;
using testing::DataPath;
using testing::NoPartialFiles;
using testing::Quote;
using testing::RunCli;
using testing::RunCommand;
using testing::ScratchDir;

long CountFrames(const fs::path& video) {
  VideoReader reader(video);
  cv::Mat frame;
  long frames = 0;
  while (reader.Read(frame)) ++frames;
  return frames;
}

// Per frame, the mean absolute difference between two videos' pixels within
// `region`.
std::vector<double> RegionDifferences(const fs::path& a, const fs::path& b, const cv::Rect& region) {
  VideoReader first(a), second(b);
  cv::Mat frame_a, frame_b;
  std::vector<double> differences;
  while (first.Read(frame_a) && second.Read(frame_b)) {
    cv::Mat difference;
    cv::absdiff(frame_a(region), frame_b(region), difference);
    const cv::Scalar mean = cv::mean(difference);
    differences.push_back((mean[0] + mean[1] + mean[2]) / 3);
  }
  return differences;
}

TEST(CliGazeTest, TrackWritesFitsGazeCsvAndOverlayForAPortrait) {
  const fs::path dir = ScratchDir("cli_track_image");
  std::string output;
  ASSERT_EQ(RunCli("track " + Quote(DataPath("images/d30.jpg")) + " -o " + Quote(dir / "fits.json") + " --csv " +
                       Quote(dir / "gaze.csv") + " --overlay " + Quote(dir / "overlay.png"),
                   &output),
            0)
      << output;
  std::ifstream stream(dir / "fits.json");
  const nlohmann::json fits = nlohmann::json::parse(stream);
  ASSERT_EQ(fits["faces"].size(), 1u);
  const nlohmann::json& face = fits["faces"][0];
  EXPECT_TRUE(face["fit"]["good"].get<bool>());
  EXPECT_TRUE(face["parameters"].contains("gaze_pitch_yaw_vergence_deg"));
  // She looks into the camera: each eye's gaze points back toward it (z < 0, within 20 degrees).
  for (const char* eye : {"left", "right"}) {
    const auto& g = face["eyes"][eye]["gaze"];
    EXPECT_LT(g[2].get<double>(), -std::cos(20 * M_PI / 180)) << eye;
  }
  std::ifstream csv(dir / "gaze.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("frame,face_id,timestamp,confidence,success,gaze_0_x", 0), 0u) << header;
  EXPECT_EQ(ReadImage(dir / "overlay.png").size(), ReadImage(DataPath("images/d30.jpg")).size());
}

TEST(CliGazeTest, TrackAnEyePatchWritesOnlyWhatWasFitted) {
  const fs::path dir = ScratchDir("cli_track_eye_patch");
  std::string output;
  // The subject looks 15 degrees toward the image right (Columbia's H), level.
  ASSERT_EQ(RunCli("track " + Quote(DataPath("columbia-eyes/0002_2m_0P_0V_15H_L.jpg")) + " --eye-patch right -o " +
                       Quote(dir / "fit.json"),
                   &output),
            0)
      << output;
  std::ifstream stream(dir / "fit.json");
  const nlohmann::json fit = nlohmann::json::parse(stream);
  const nlohmann::json& face = fit["faces"][0];
  // No face was detected, so no landmarks, box or head pose are invented.
  EXPECT_FALSE(face.contains("landmarks"));
  EXPECT_FALSE(face.contains("head_pose"));
  EXPECT_TRUE(face["eyes"].contains("right"));
  EXPECT_FALSE(face["eyes"].contains("left"));
  EXPECT_GT(face["eyes"]["right"]["yaw_deg"].get<double>(), 5.0);
}

// Eye patches tracked together, each as alone, into one folder; a video
// among them is refused before any work, since it is no eye patch.
TEST(CliGazeTest, TrackSeveralEyePatchesIntoAFolder) {
  const fs::path dir = ScratchDir("cli_track_batch");
  const std::vector<std::string> crops = {"0013_2m_0P_0V_0H_R.jpg", "0013_2m_0P_10V_5H_R.jpg", "0013_2m_15P_-10V_-5H_R.jpg"};
  std::string inputs;
  for (const std::string& crop : crops) inputs += Quote(DataPath("columbia-eyes/" + crop)) + " ";
  std::string output;
  ASSERT_EQ(RunCli("track --eye-patch right " + inputs + "-o " + Quote(dir / "fits") + " --csv " + Quote(dir / "fits"), &output), 0)
      << output;
  EXPECT_NE(output.find("info: [2/3] 0013_2m_0P_10V_5H_R.jpg: right eye: gaze pitch"), std::string::npos) << output;
  for (const std::string& crop : crops) {
    const std::string stem = fs::path(crop).stem().string();
    EXPECT_TRUE(fs::exists(dir / "fits" / (stem + ".json")) && fs::exists(dir / "fits" / (stem + ".csv"))) << crop;
  }
  ASSERT_EQ(RunCli("track --eye-patch right " + Quote(DataPath("columbia-eyes/" + crops[1])) + " -o " +
                       Quote(dir / "alone.json") + " -q",
                   &output),
            0)
      << output;
  EXPECT_EQ(testing::ReadText(dir / "fits" / "0013_2m_0P_10V_5H_R.json"), testing::ReadText(dir / "alone.json"));
  EXPECT_EQ(RunCli("track --eye-patch right " + inputs + Quote(DataPath("video/d19.mp4")) + " -o " + Quote(dir / "never"),
                   &output),
            2)
      << output;
  EXPECT_NE(output.find("--eye-patch takes an image of one eye, not a video"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(dir / "never"));
}

TEST(CliGazeTest, RedirectAnImageToEyeContactWithDebugPictures) {
  const fs::path dir = ScratchDir("cli_redirect_image");
  std::string output;
  ASSERT_EQ(RunCli("redirect " + Quote(DataPath("images/d19.jpg")) + " -o " + Quote(dir / "out.jpg") +
                       " --look-at camera --side-by-side --debug-dir " + Quote(dir / "debug") +
                       " --debug-frames 3 --refit",
                   &output),
            0)
      << output;
  // --refit is for a video's stored fits and --debug-frames chooses a video's frames: an image says
  // they change nothing.
  EXPECT_NE(output.find("--refit: an image is fitted anew on every run"), std::string::npos) << output;
  EXPECT_NE(output.find("--debug-frames chooses a video's frames"), std::string::npos) << output;
  const cv::Mat input = ReadImage(DataPath("images/d19.jpg")), result = ReadImage(dir / "out.jpg");
  EXPECT_EQ(result.cols, 2 * input.cols);
  EXPECT_EQ(result.rows, input.rows);
  // The photo's EXIF comes along (io/photo_metadata_test.cc tests what it says).
  EXPECT_FALSE(PhotoMetadata::Read(dir / "out.jpg").empty());
  for (const char* name : {"fit_overlay.png", "flow.png", "eyeball_mask.png", "skin_mask.png", "eyeball_layer.png"}) {
    EXPECT_TRUE(fs::exists(dir / "debug" / name)) << name;
  }
  EXPECT_NE(output.find("redirected"), std::string::npos) << output;
  EXPECT_EQ(output.find("beyond the eyes' reach"), std::string::npos) << output;
}

TEST(CliGazeTest, RedirectKeepsASixteenBitPhotosAlphaAndEveryPixelAwayFromTheEyes) {
  const fs::path dir = ScratchDir("cli_redirect_deep");
  const cv::Mat photo = ReadImage(DataPath("images/d30.jpg"));
  cv::Mat deep;
  photo.convertTo(deep, CV_16U, 257.0);
  deep += cv::Scalar::all(77);  // low bits an 8-bit round trip would lose
  std::vector<cv::Mat> planes;
  cv::split(deep, planes);
  planes.emplace_back(photo.size(), CV_16U);
  for (int y = 0; y < photo.rows; ++y) planes.back().row(y).setTo(cv::Scalar(65535 - 50 * y));
  cv::Mat deep_alpha;
  cv::merge(planes, deep_alpha);
  ASSERT_TRUE(cv::imwrite((dir / "in.png").string(), deep_alpha));
  std::string output;
  ASSERT_EQ(RunCli("redirect " + Quote(dir / "in.png") + " -o " + Quote(dir / "out.png") + " --look-at camera", &output), 0)
      << output;
  const cv::Mat result = cv::imread((dir / "out.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(result.type(), CV_16UC4);
  cv::Mat in_alpha, out_alpha;
  cv::extractChannel(deep_alpha, in_alpha, 3);
  cv::extractChannel(result, out_alpha, 3);
  EXPECT_EQ(cv::norm(in_alpha, out_alpha, cv::NORM_INF), 0);
  cv::Mat differs;
  cv::compare(result.reshape(1), deep_alpha.reshape(1), differs, cv::CMP_NE);
  const int changed = cv::countNonZero(differs);
  // The eyes changed (a few thousand values), nothing else did.
  EXPECT_GT(changed, 300);
  EXPECT_LT(changed, 0.02 * photo.total() * 3);
}

TEST(CliGazeTest, RedirectColumbiaScoresOneSubjectRegisteredAndAsCut) {
  const fs::path dir = ScratchDir("cli_redirect_columbia");
  auto run = [&](const std::string& extra) {
    std::string output;
    EXPECT_EQ(RunCli("eval redirect-columbia --subjects 0007 --json --plot " + Quote(dir / "curves.png") + extra, &output), 0)
        << output;
    return nlohmann::json::parse(output.substr(output.find('{')));
  };
  const nlohmann::json registered = run(" --out-dir " + Quote(dir / "out"));
  const nlohmann::json as_cut = run(" --no-register");
  // Both eyes' crops at head pose 0 but the source 0V 0H one.
  EXPECT_GE(registered["crops"].get<int>(), 30);
  EXPECT_TRUE(registered["registered"].get<bool>());
  EXPECT_FALSE(as_cut["registered"].get<bool>());
  EXPECT_EQ(registered["fit_options"]["work_width"].get<int>(), 128);  // what the crops were fitted with
  // Registering removes the crops' landmark framing from every comparison.
  EXPECT_LT(registered["error_none"].get<double>(), as_cut["error_none"].get<double>());
  EXPECT_LT(registered["error_full"].get<double>(), registered["error_none"].get<double>());
  EXPECT_TRUE(fs::exists(dir / "curves.png"));
  EXPECT_TRUE(fs::exists(dir / "out" / "0007_2m_0P_10V_15H_L.jpg"));
}

TEST(CliGazeTest, ColumbiaLeavesOutExcludedSubjects) {
  // The paper's protocol leaves out people wearing glasses.
  const fs::path dir = ScratchDir("cli_columbia_exclude");
  std::string output;
  ASSERT_EQ(RunCli("eval columbia --subjects 0007 0013 --exclude-subjects 0007 --poses 0 --every 10 --csv " +
                       Quote(dir / "crops.csv") + " --plot " + Quote(dir / "curves.png") + " --json --fit truncation=0.07",
                   &output),
            0)
      << output;
  // The figures come with the fit options they were measured with.
  const nlohmann::json result = nlohmann::json::parse(output.substr(output.find('{')));
  EXPECT_DOUBLE_EQ(result["fit_options"]["truncation"].get<double>(), 0.07);
  EXPECT_EQ(result["fit_options"]["work_width"].get<int>(), 128);  // the 64 px crops, resampled
  // Photos 1, 11 and 21 of 0013's 21 at head pose 0, both eyes: the face's figures count photos.
  EXPECT_EQ(result["photos"].get<int>(), 3);
  EXPECT_EQ(result["crops"].get<int>(), 6);
  EXPECT_EQ(result["one_eye"]["crops"].get<int>(), 6);
  EXPECT_EQ(result["by_head_pose"]["0"]["photos"].get<int>(), 3);
  // Excluded subjects are not listed by subject either; one subject leaves the resampling no spread.
  EXPECT_EQ(result["by_subject"].size(), 1u);
  EXPECT_EQ(result["by_subject"]["0013"]["photos"].get<int>(), 3);
  EXPECT_EQ(result["subject_resampling"]["subjects"].get<int>(), 1);
  // The appearance gaze prior never saw the subject it reads.
  EXPECT_NE(result["appearance_prior"].get<std::string>().find("each evaluated subject left out"), std::string::npos);
  EXPECT_NEAR(result["subject_resampling"]["pitch_mean_p95_deg"].get<double>(), result["pitch_mean_deg"].get<double>(), 1e-3);
  // The head's yaw was read from the crops: 0013's three frontal photos, read within 10 degrees of
  // facing the camera, one person, so no spread between people.
  const nlohmann::json& head = result["head_yaw_reading"]["0"];
  EXPECT_EQ(head["photos"].get<int>(), 3);
  EXPECT_EQ(head["subjects"].get<int>(), 1);
  EXPECT_DOUBLE_EQ(head["subject_spread_deg"].get<double>(), 0);
  EXPECT_LT(head["abs_error_mean_deg"].get<double>(), 10);
  // Given the head's yaw, there is no reading to summarise.
  ASSERT_EQ(RunCli("eval columbia --subjects 0013 --poses 0 --every 10 --known-head-pose --plot " +
                       Quote(dir / "known.png") + " --json",
                   &output),
            0)
      << output;
  const nlohmann::json known = nlohmann::json::parse(output.substr(output.find('{')));
  EXPECT_EQ(known["photos"].get<int>(), 3);
  EXPECT_FALSE(known.contains("head_yaw_reading"));
  std::ifstream csv(dir / "crops.csv");
  std::string line;
  std::getline(csv, line);  // header
  int rows = 0;
  std::vector<double> zero_pitch_errors;  // the always-zero predictor errs by the label
  while (std::getline(csv, line)) {
    EXPECT_EQ(line.substr(0, 5), "0013_") << line;
    std::vector<std::string> fields;
    std::stringstream row(line);
    for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
    ASSERT_GT(fields.size(), 3u) << line;
    zero_pitch_errors.push_back(std::abs(std::stod(fields[3])));  // label_pitch
    ++rows;
  }
  EXPECT_EQ(rows, 6);  // photos 1, 11 and 21 of 0013's 21 at head pose 0, both eyes
  // Each photo's two rows carry the same label, so the rows' median is the photos'.
  EXPECT_DOUBLE_EQ(result["zero_pitch_median_deg"].get<double>(), Median(zero_pitch_errors));
  EXPECT_EQ(RunCli("eval columbia --subjects 0007 --exclude-subjects 0007", &output), 4) << output;  // bad input
  EXPECT_NE(output.find("no crops"), std::string::npos) << output;
  EXPECT_EQ(RunCli("eval columbia --subjects 0013 --appearance-training " + Quote(dir / "missing"), &output), 4) << output;
  EXPECT_NE(output.find("no such folder"), std::string::npos) << output;
}

// Links subjects 0013's and 0014's Columbia crops at head pose 0 into a new
// folder `crops`; returns how many.
int LinkFrontalCrops(const fs::path& crops) {
  fs::create_directories(crops);
  int linked = 0;
  for (const auto& entry : fs::directory_iterator(DataPath("columbia-eyes"))) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("0013_2m_0P_", 0) == 0 || name.rfind("0014_2m_0P_", 0) == 0) {
      fs::create_symlink(entry.path(), crops / name);
      ++linked;
    }
  }
  return linked;
}

// train-appearance makes a model that track --eye-patch's prior could load,
// from a folder of labelled crops; a folder without any fails and writes nothing.
TEST(CliGazeTest, TrainAppearanceWritesAModelFromLabelledCrops) {
  const fs::path dir = ScratchDir("cli_train_appearance");
  const fs::path crops = dir / "crops";
  ASSERT_EQ(LinkFrontalCrops(crops), 84);
  std::string output;
  ASSERT_EQ(RunCli("train-appearance " + Quote(crops) + " -o " + Quote(dir / "gaze.cbor"), &output), 0) << output;
  std::ifstream stream(dir / "gaze.cbor", std::ios::binary);
  const nlohmann::json model = nlohmann::json::from_cbor(stream);
  for (const char* angle : {"pitch", "frontal_yaw", "camera_yaw", "turned_yaw", "head_yaw"}) {
    EXPECT_EQ(model["samples"][angle].get<int>(), 84) << angle;  // all frontal
  }
  EXPECT_EQ(model["subjects"], nlohmann::json({"0013", "0014"}));
  EXPECT_EQ(model["head_yaw_slope"].get<double>(), 1.0);  // every head faces the camera: nothing to learn it from
  // Every crop is an exemplar: its 8 x 12 band, 324 gradient bins and the
  // eye's side, as floats; each regression has a weight per exemplar.
  EXPECT_EQ(model["exemplar_count"].get<int>(), 84);
  EXPECT_EQ(model["exemplars"].get_binary().size(), 84u * 421 * sizeof(float));
  for (const char* regression :
       {"pitch", "frontal_mirrored_yaw", "mirrored_camera_yaw", "mirrored_turned_yaw", "mirrored_head_yaw"}) {
    EXPECT_EQ(model["regressions"][regression]["weights"].size(), 84u) << regression;
    // With every head facing the camera the head turns' term has nothing to
    // tell apart; the weights are numbers, not NaN (a file that would not load).
    for (const nlohmann::json& weight : model["regressions"][regression]["weights"]) {
      ASSERT_TRUE(weight.is_number()) << regression;
    }
  }
  EXPECT_EQ(RunCli("train-appearance " + Quote(dir / "gaze.cbor") + " -o " + Quote(dir / "none.json"), &output), 4)
      << output;
  fs::create_directories(dir / "nothing");
  std::ofstream(dir / "nothing" / "notes.txt") << "no crops here";
  EXPECT_EQ(RunCli("train-appearance " + Quote(dir / "nothing") + " -o " + Quote(dir / "none.json"), &output), 4) << output;
  EXPECT_NE(output.find("no files named like"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(dir / "none.json"));
  EXPECT_TRUE(NoPartialFiles(dir));
}

// Evaluating a folder that is also the appearance prior's training folder
// lists it once: a stray file is warned about once, and the prior is trained
// on every crop there, the evaluated subject's own left out.
TEST(CliGazeTest, ColumbiaTrainedOnTheEvaluatedFolderListsItOnce) {
  const fs::path dir = ScratchDir("cli_columbia_same_folder");
  const fs::path crops = dir / "crops";
  ASSERT_EQ(LinkFrontalCrops(crops), 84);
  std::ofstream(crops / "notes.txt") << "not a crop\n";
  std::string output;
  ASSERT_EQ(RunCli("eval columbia " + Quote(crops) + " --appearance-training " + Quote(crops) +
                       " --subjects 0013 --every 10 --json --plot " + Quote(dir / "curves.png"),
                   &output),
            0)
      << output;
  const std::string warning = "skipped 1 file(s) not named like";
  const std::size_t first = output.find(warning);
  ASSERT_NE(first, std::string::npos) << output;
  EXPECT_EQ(output.find(warning, first + 1), std::string::npos) << output;
  const nlohmann::json result = nlohmann::json::parse(output.substr(output.find('{')));
  EXPECT_EQ(result["photos"].get<int>(), 3);  // photos 1, 11 and 21 of 0013's 21
  EXPECT_NE(result["appearance_prior"].get<std::string>().find("trained on 84 crops of 2 subjects"), std::string::npos)
      << result["appearance_prior"];
}

// A fit whose iris sits off the photo's would show a broken iris when
// redirected: the face is left as it was, unless the check is turned off.
// s42.jpg's fit, its gaze edited 25 degrees aside (until session 63 her own
// fit was such a one: the vergence prior held her converging eyes parallel).
TEST(CliGazeTest, RedirectLeavesAFaceWhoseFittedIrisIsOffItsEye) {
  const fs::path dir = ScratchDir("cli_redirect_iris_offset");
  const fs::path photo = DataPath("images/s42.jpg");
  std::string output;
  ASSERT_EQ(RunCli("track " + Quote(photo) + " -o " + Quote(dir / "fits.json"), &output), 0) << output;
  nlohmann::json fits = nlohmann::json::parse(testing::ReadText(dir / "fits.json"));
  ASSERT_EQ(fits["faces"].size(), 1u);
  fits["faces"][0]["parameters"]["gaze_pitch_yaw_vergence_deg"][1] =
      fits["faces"][0]["parameters"]["gaze_pitch_yaw_vergence_deg"][1].get<double>() + 25;
  std::ofstream(dir / "aside.json") << fits.dump();
  const std::string aside = " --fits " + Quote(dir / "aside.json");

  ASSERT_EQ(RunCli("redirect " + Quote(photo) + " -o " + Quote(dir / "tracked.png") + " --fits " +
                       Quote(dir / "fits.json"),
                   &output),
            0)
      << output;
  EXPECT_NE(output.find("1 of 1 face redirected"), std::string::npos) << output;
  ASSERT_EQ(RunCli("redirect " + Quote(photo) + " -o " + Quote(dir / "kept.png") + aside, &output), 0) << output;
  EXPECT_NE(output.find("left untouched: a fitted iris sits"), std::string::npos) << output;
  EXPECT_NE(output.find("0 of 1 face redirected"), std::string::npos) << output;
  const cv::Mat input = ReadImage(photo);
  cv::Mat difference;
  cv::absdiff(ReadImage(dir / "kept.png"), input, difference);
  EXPECT_EQ(cv::countNonZero(difference.reshape(1)), 0);
  ASSERT_EQ(RunCli("redirect " + Quote(photo) + " -o " + Quote(dir / "forced.png") + aside + " --max-iris-offset 0",
                   &output),
            0)
      << output;
  EXPECT_NE(output.find("1 of 1 face redirected"), std::string::npos) << output;
  cv::absdiff(ReadImage(dir / "forced.png"), input, difference);
  EXPECT_GT(cv::countNonZero(difference.reshape(1)), 100);
  EXPECT_EQ(RunCli("redirect " + Quote(photo) + " -o " + Quote(dir / "bad.png") + " --max-iris-offset -1", &output), 2)
      << output;
}

// `eval iris` measures a photo's fits as tracked now or as stored by `track`,
// and refuses another photo's fits.
TEST(CliGazeTest, EvalIrisMeasuresTrackedAndStoredFits) {
  const fs::path dir = ScratchDir("cli_eval_iris");
  const std::string photo = Quote(DataPath("images/d30.jpg"));
  std::string output;
  ASSERT_EQ(RunCli("eval iris " + photo + " --json", &output), 0) << output;
  const nlohmann::json now = nlohmann::json::parse(output.substr(output.find('{')));
  EXPECT_EQ(now["eyes"], 2);
  EXPECT_LT(now["median"].get<double>(), 0.45);  // 0.33: both fitted irises on the photo's
  ASSERT_EQ(RunCli("track " + photo + " -o " + Quote(dir / "d30.jsonl"), &output), 0) << output;
  ASSERT_EQ(RunCli("eval iris " + photo + " --fits " + Quote(dir / "d30.jsonl") + " --json --csv " + Quote(dir / "eyes.csv"),
                   &output),
            0)
      << output;
  const nlohmann::json stored = nlohmann::json::parse(output.substr(output.find('{')));
  EXPECT_NEAR(stored["median"].get<double>(), now["median"].get<double>(), 1e-3);
  std::stringstream csv(testing::ReadText(dir / "eyes.csv"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(csv, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "frame,face_id,eye,iris_misalignment");
  EXPECT_EQ(lines[1].rfind("0,0,left,", 0), 0u) << lines[1];
  EXPECT_EQ(RunCli("eval iris " + Quote(DataPath("images/d19.jpg")) + " --fits " + Quote(dir / "d30.jsonl"), &output), 4)
      << output;
  EXPECT_NE(output.find("the fits were made on"), std::string::npos) << output;
}

TEST(CliGazeTest, BadTargetsAndNoFacesFailCleanly) {
  const fs::path dir = ScratchDir("cli_redirect_bad");
  std::string output;
  EXPECT_EQ(RunCli("redirect " + Quote(DataPath("images/d30.jpg")) + " -o " + Quote(dir / "a.jpg") + " --look-at 1,2", &output), 2)
      << output;
  EXPECT_EQ(RunCli("redirect " + Quote(DataPath("images/d30.jpg")) + " -o " + Quote(dir / "b.jpg") +
                       " --look-at camera --offset 1,2",
                   &output),
            2)
      << output;
  // --debug-frames chooses which pictures --debug-dir gets, so it needs it.
  EXPECT_EQ(RunCli("redirect " + Quote(DataPath("images/d30.jpg")) + " -o " + Quote(dir / "a.jpg") + " --debug-frames 3",
                   &output),
            2)
      << output;
  EXPECT_NE(output.find("--debug-frames requires --debug-dir"), std::string::npos) << output;
  for (const std::string target : {"--gaze 1000,0", "--gaze nan,0", "--offset 0,400"}) {
    EXPECT_EQ(RunCli("redirect " + Quote(DataPath("images/d30.jpg")) + " -o " + Quote(dir / "a.jpg") + " " + target,
                     &output),
              2)
        << target << ": " << output;
    EXPECT_NE(output.find("within -90 to 90"), std::string::npos) << output;
  }
  // An image's output is an image, of any format it can be written in; the message lists them.
  EXPECT_EQ(RunCli("redirect " + Quote(DataPath("images/d30.jpg")) + " -o " + Quote(dir / "d.mp4"), &output), 2) << output;
  EXPECT_NE(output.find("an image's output is an image (.png, .jpg, .jpeg, .tif, .tiff, .webp, .bmp)"), std::string::npos)
      << output;
  EXPECT_EQ(RunCli("redirect " + Quote(DataPath("images/s39.jpg")) + " -o " + Quote(dir / "cat.jpg"), &output), 3) << output;
  EXPECT_NE(output.find("no face"), std::string::npos) << output;
  // So does a video without a face in any frame (it was copied unchanged with exit code 0), and writes
  // nothing: not the video, nor the fits kept for a re-run (they held only empty frames).
  ASSERT_EQ(RunCommand("ffmpeg -v error -y -loop 1 -i " + Quote(DataPath("images/s39.jpg")) +
                       " -t 0.4 -r 10 -vf scale=540:720 -pix_fmt yuv420p " + Quote(dir / "cat.mp4")),
            0);
  EXPECT_EQ(RunCli("redirect " + Quote(dir / "cat.mp4") + " -o " + Quote(dir / "cat_out.mp4"), &output), 3) << output;
  EXPECT_NE(output.find("no face found in any of the 4 frames"), std::string::npos) << output;
  EXPECT_FALSE(std::filesystem::exists(dir / "cat_out.mp4"));
  EXPECT_FALSE(std::filesystem::exists(dir / "cat_out.mp4.fits.jsonl"));
  EXPECT_TRUE(NoPartialFiles(dir));
  // Another photo's fits would draw its eyes in the wrong places.
  ASSERT_EQ(RunCli("track " + Quote(DataPath("images/d30.jpg")) + " -o " + Quote(dir / "d30.jsonl"), &output), 0) << output;
  EXPECT_EQ(RunCli("redirect " + Quote(DataPath("images/d19.jpg")) + " --fits " + Quote(dir / "d30.jsonl") + " -o " +
                       Quote(dir / "c.jpg"),
                   &output),
            4)
      << output;
  EXPECT_NE(output.find("the fits were made on 600x900 frames"), std::string::npos) << output;
  // A point behind the head is no error: the eyes look as far toward it as they turn, and the command says so.
  EXPECT_EQ(RunCli("redirect " + Quote(DataPath("images/d30.jpg")) + " --fits " + Quote(dir / "d30.jsonl") + " -o " +
                       Quote(dir / "behind.jpg") + " --look-at 0,0,5000",
                   &output),
            0)
      << output;
  EXPECT_NE(output.find("face 0: the point (0, 0, 5000) mm lies beyond the eyes' reach"), std::string::npos) << output;
  // A gaze script given for an image: the image takes its target at 0 s, and says the later segments go unused.
  {
    std::ofstream script(dir / "script.json");
    script << R"({"segments": [{"start_s": 0, "target": "camera"}, {"start_s": 2, "target": {"gaze": [0, 20]}}]})";
  }
  EXPECT_EQ(RunCli("redirect " + Quote(DataPath("images/d30.jpg")) + " --fits " + Quote(dir / "d30.jsonl") + " -o " +
                       Quote(dir / "scripted.jpg") + " --script " + Quote(dir / "script.json"),
                   &output),
            0)
      << output;
  EXPECT_NE(output.find("an image takes the gaze script's target at 0 s, so the gaze script's segment starting at 2 s "
                        "is not used"),
            std::string::npos)
      << output;
  {
    std::ofstream script(dir / "bad_script.json");
    script << R"({"segments": [{"start_s": 0, "target": {"look_at": "there"}}]})";
  }
  EXPECT_EQ(RunCli("redirect " + Quote(DataPath("video/d19.mp4")) + " -o " + Quote(dir / "v.mp4") + " --script " +
                       Quote(dir / "bad_script.json"),
                   &output),
            4)
      << output;
  // The input as the output is refused before any work, and left as it was.
  fs::copy_file(DataPath("images/d30.jpg"), dir / "own.jpg", fs::copy_options::overwrite_existing);
  EXPECT_EQ(RunCli("redirect " + Quote(dir / "own.jpg") + " -o " + Quote(dir / "." / "own.jpg"), &output), 6) << output;
  EXPECT_NE(output.find("refusing to overwrite the input"), std::string::npos) << output;
  EXPECT_EQ(output.find("redirected"), std::string::npos) << output;
  EXPECT_EQ(testing::ReadText(dir / "own.jpg"), testing::ReadText(DataPath("images/d30.jpg")));
  EXPECT_FALSE(fs::exists(dir / "a.jpg") || fs::exists(dir / "b.jpg") || fs::exists(dir / "c.jpg") || fs::exists(dir / "d.mp4") ||
               fs::exists(dir / "cat.jpg") || fs::exists(dir / "v.mp4"));
  EXPECT_TRUE(NoPartialFiles(dir));
}

// Several inputs, a folder among them, go into an output folder under their
// own names, each as a run on it alone would write it; a folder's empty file
// and a photo without a face are reported by name and the rest are still
// written.
TEST(CliGazeTest, RedirectsSeveralInputsIntoAFolderAsEachAlone) {
  const fs::path dir = ScratchDir("cli_redirect_batch");
  fs::create_directories(dir / "in");
  fs::copy_file(DataPath("images/d30.jpg"), dir / "in" / "d30.jpg", fs::copy_options::overwrite_existing);
  fs::copy_file(DataPath("images/s39.jpg"), dir / "in" / "s39 cat 100%.jpg", fs::copy_options::overwrite_existing);
  std::ofstream(dir / "in" / "notes.txt") << "not a photo";
  std::ofstream(dir / "in" / "empty.jpg").close();  // a folder's file that cannot be read fails in its turn
  std::string output;
  EXPECT_EQ(RunCli("redirect " + Quote(dir / "in") + " " + Quote(DataPath("images/s12.jpg")) + " -o " + Quote(dir / "out"),
                   &output),
            4)
      << output;
  EXPECT_NE(output.find("error: [2/4] empty.jpg: " + (dir / "in" / "empty.jpg").string() + ": the file is empty"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("error: [3/4] s39 cat 100%.jpg: no face found"), std::string::npos) << output;
  EXPECT_NE(output.find("info: [4/4] s12.jpg: 1 of 1 face redirected"), std::string::npos) << output;
  EXPECT_NE(output.find("2 of 4 inputs did not go through: empty.jpg (bad input), s39 cat 100%.jpg (no face)"),
            std::string::npos)
      << output;
  std::vector<std::string> written;
  for (const auto& entry : fs::directory_iterator(dir / "out")) written.push_back(entry.path().filename().string());
  std::sort(written.begin(), written.end());
  EXPECT_EQ(written, (std::vector<std::string>{"d30.jpg", "s12.jpg"}));
  ASSERT_EQ(RunCli("redirect " + Quote(DataPath("images/d30.jpg")) + " -o " + Quote(dir / "alone.jpg") + " -q", &output), 0)
      << output;
  EXPECT_EQ(testing::ReadText(dir / "out" / "d30.jpg"), testing::ReadText(dir / "alone.jpg"));

  // What would go wrong is refused before any work, with nothing written.
  const std::string inputs = Quote(dir / "in") + " " + Quote(DataPath("images/s12.jpg"));
  EXPECT_EQ(RunCli("redirect " + inputs + " " + Quote(dir / "missing.jpg") + " -o " + Quote(dir / "never"), &output), 4)
      << output;
  EXPECT_NE(output.find("missing.jpg: no such file"), std::string::npos) << output;
  EXPECT_EQ(RunCli("redirect " + inputs + " -o " + Quote(dir / "never.jpg"), &output), 2) << output;
  EXPECT_NE(output.find("several inputs are written into a folder"), std::string::npos) << output;
  EXPECT_EQ(RunCli("redirect " + inputs + " -o " + Quote(dir / "never") + " --fits " + Quote(dir / "alone.jpg"), &output), 2)
      << output;
  EXPECT_EQ(RunCli("redirect " + inputs + " " + Quote(DataPath("images/d30.jpg")) + " -o " + Quote(dir / "never"), &output), 2)
      << output;
  EXPECT_NE(output.find("would both be written to"), std::string::npos) << output;
  EXPECT_EQ(RunCli("redirect " + inputs + " -o " + Quote(dir / "in"), &output), 6) << output;
  EXPECT_NE(output.find("refusing to overwrite the input"), std::string::npos) << output;
  EXPECT_EQ(testing::ReadText(dir / "in" / "d30.jpg"), testing::ReadText(DataPath("images/d30.jpg")));
  EXPECT_EQ(RunCli("redirect " + inputs + " -o " + Quote(dir / "never") + " --fx -5", &output), 2) << output;
  EXPECT_NE(output.find("focal lengths must be positive"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(dir / "never") || fs::exists(dir / "never.jpg"));
  EXPECT_TRUE(NoPartialFiles(dir));
}

// An output that cannot be written fails at once, before any fitting, and
// leaves the other outputs unwritten: nothing is half done.
TEST(CliGazeTest, AnUnwritableOutputFailsBeforeAnyWork) {
  const fs::path dir = ScratchDir("cli_unwritable");
  const std::string nowhere = "/proc/gazedirector_cli_test";  // /proc takes no new files, even as root
  std::string output;
  EXPECT_EQ(RunCli("track " + Quote(DataPath("images/d30.jpg")) + " -o " + Quote(dir / "fits.jsonl") + " --csv " +
                       nowhere + ".csv",
                   &output),
            6)
      << output;
  EXPECT_NE(output.find("cannot write " + nowhere + ".csv"), std::string::npos) << output;
  EXPECT_EQ(output.find("gaze pitch"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(dir / "fits.jsonl"));
  // The evaluation would fit for minutes before writing its figure.
  EXPECT_EQ(RunCli("eval columbia --subjects 0013 --poses 0 --every 10 --plot " + nowhere + ".png --csv " +
                       Quote(dir / "crops.csv"),
                   &output),
            6)
      << output;
  EXPECT_EQ(output.find("appearance gaze"), std::string::npos) << output;
  std::ofstream(dir / "notes.txt") << "a file, not a folder";
  EXPECT_EQ(RunCli("eval redirect-columbia --subjects 0007 --plot " + Quote(dir / "curves.png") + " --out-dir " +
                       Quote(dir / "notes.txt" / "crops"),
                   &output),
            6)
      << output;
  EXPECT_EQ(output.find("registered"), std::string::npos) << output;
  EXPECT_EQ(RunCli("redirect " + Quote(DataPath("images/d30.jpg")) + " -o " + Quote(dir / "out.jpg") +
                       " --debug-dir " + nowhere,
                   &output),
            6)
      << output;
  EXPECT_FALSE(fs::exists(dir / "out.jpg") || fs::exists(dir / "crops.csv") || fs::exists(dir / "curves.png"));
  EXPECT_TRUE(NoPartialFiles(dir));
}

TEST(CliGazeTest, VideoRedirectKeepsEveryFrameAndReusesItsFits) {
  const fs::path dir = ScratchDir("cli_redirect_video");
  const fs::path input = DataPath("video/d19.mp4");
  std::string output;
  ASSERT_EQ(RunCli("redirect " + Quote(input) + " -o " + Quote(dir / "camera.mp4") + " --look-at camera", &output), 0)
      << output;
  EXPECT_EQ(CountFrames(dir / "camera.mp4"), CountFrames(input));
  const fs::path fits = dir / "camera.mp4.fits.jsonl";
  ASSERT_TRUE(fs::exists(fits));
  // d19 blinks once (frames 92-95): those frames are marked and left as they were.
  std::vector<long> blinks;
  cv::Rect eyes;
  {
    std::ifstream lines(fits);
    std::string line;
    for (long index = 0; std::getline(lines, line); ++index) {
      const nlohmann::json record = nlohmann::json::parse(line);
      if (record["faces"].empty()) continue;
      const nlohmann::json& face = record["faces"][0];
      if (face["fit"].value("eyes_closed", false)) blinks.push_back(index);
      if (index == 0) {
        std::vector<cv::Point> points;
        for (int k = 36; k < 48; ++k) points.emplace_back(face["landmarks"][k][0], face["landmarks"][k][1]);
        eyes = cv::boundingRect(points);
      }
    }
  }
  ASSERT_FALSE(blinks.empty());
  EXPECT_LT(blinks.size(), 10u);
  const std::vector<double> changed = RegionDifferences(input, dir / "camera.mp4", eyes);
  ASSERT_GT(changed.size(), static_cast<std::size_t>(blinks.back()));
  // Re-encoding alone differs by about 2.8 grey levels there; eyes turned to the camera by about 10.
  for (long blink : blinks) EXPECT_LT(changed[blink], 4.0) << "frame " << blink;
  EXPECT_GT(changed[10], 6.0);
  // A second run re-renders from the stored fits, without tracking again.
  ASSERT_EQ(RunCli("redirect " + Quote(input) + " -o " + Quote(dir / "camera.mp4") + " --offset 0,10", &output), 0) << output;
  EXPECT_NE(output.find("reusing the fits"), std::string::npos) << output;
  // Two stages: edited fits are used as given. Debugging pictures of the frames asked for: all of
  // them for a redirected frame, the fit's overlay alone for a blink left as it was; a frame past
  // the end is named.
  ASSERT_EQ(RunCli("redirect " + Quote(input) + " --fits " + Quote(fits) + " -o " + Quote(dir / "left.mp4") +
                       " --gaze 0,-20 --frame head --debug-dir " + Quote(dir / "debug") +
                       fmt::format(" --debug-frames 10,{},5000", blinks.front()),
                   &output),
            0)
      << output;
  EXPECT_EQ(CountFrames(dir / "left.mp4"), CountFrames(input));
  EXPECT_EQ(output.find("beyond the eyes' reach"), std::string::npos) << output;
  EXPECT_NE(output.find("so frame 5000 had no pictures"), std::string::npos) << output;
  std::vector<std::string> pictures;
  for (const auto& entry : fs::directory_iterator(dir / "debug")) pictures.push_back(entry.path().filename().string());
  const std::string blink = fmt::format("frame{:05d}_fit_overlay.png", blinks.front());
  EXPECT_EQ(std::count(pictures.begin(), pictures.end(), blink), 1) << fmt::format("{}", fmt::join(pictures, " "));
  for (const char* name : {"fit_overlay.png", "flow.png", "eyeball_mask.png", "skin_mask.png", "eyeball_layer.png"}) {
    EXPECT_TRUE(fs::exists(dir / "debug" / (std::string("frame00010_") + name))) << name;
  }
  for (const std::string& picture : pictures) {
    EXPECT_TRUE(picture.rfind("frame00010_", 0) == 0 || picture == blink) << picture;
  }
  const cv::Mat overlay = ReadImage(dir / "debug" / "frame00010_fit_overlay.png");
  EXPECT_EQ(overlay.size(), ReadImage(dir / "debug" / blink).size());
  // A point behind her head: the eyes turn as far toward it as they can, and the command says so once.
  // Without --debug-frames, ten frames spread from the first to the last get pictures.
  ASSERT_EQ(RunCli("redirect " + Quote(input) + " --fits " + Quote(fits) + " -o " + Quote(dir / "behind.mp4") +
                       " --look-at 0,0,5000 --debug-dir " + Quote(dir / "spread"),
                   &output),
            0)
      << output;
  std::set<std::string> spread;
  for (const auto& entry : fs::directory_iterator(dir / "spread")) spread.insert(entry.path().filename().string().substr(0, 10));
  EXPECT_EQ(spread.size(), 10u) << fmt::format("{}", fmt::join(spread, " "));
  EXPECT_TRUE(spread.contains("frame00000"));
  EXPECT_TRUE(spread.contains(fmt::format("frame{:05d}", CountFrames(input) - 1))) << fmt::format("{}", fmt::join(spread, " "));
  const std::string warning = "target lay beyond the eyes' reach";
  const auto warned = output.find(warning);
  ASSERT_NE(warned, std::string::npos) << output;
  EXPECT_EQ(output.find("beyond the eyes' reach", warned + warning.size()), std::string::npos) << output;
  EXPECT_TRUE(NoPartialFiles(dir));
}


// Ctrl-C during long work: the command stops with exit code 130 and one line,
// and none of its outputs is left, whole or partial. The signal is sent once
// the command reports its first tenth of the video's frames, so that it
// arrives in the middle of the work rather than before the handlers are set.
TEST(CliGazeTest, AnInterruptedVideoLeavesNoOutputs) {
  const std::string video = Quote(DataPath("video/d3.mp4"));
  const struct {
    std::string name, arguments;
  } commands[] = {
      {"track", "track " + video + " -o fits.jsonl --csv gaze.csv --overlay overlay.mp4"},
      {"redirect", "redirect " + video + " -o out.mp4 --side-by-side"},
  };
  for (const auto& command : commands) {
    const fs::path dir = ScratchDir("cli_interrupted_" + command.name);
    const std::string script = fmt::format(
        "cd {} && ({} {} > log 2>&1 & pid=$!; "
        "for i in $(seq 1 600); do grep -q ' frames (' log && break; sleep 0.1; done; "
        "kill -INT $pid; wait $pid; echo \"exit $?\"; cat log; rm log)",
        Quote(dir), Quote(CliPath()), command.arguments);
    std::string output;
    ASSERT_EQ(RunCommand(script, &output), 0) << output;
    EXPECT_NE(output.find("exit 130"), std::string::npos) << command.name << ": " << output;
    EXPECT_NE(output.find("gazedirector: error: interrupted; partial outputs removed"), std::string::npos) << output;
    std::vector<std::string> left;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) left.push_back(entry.path().filename().string());
    EXPECT_TRUE(left.empty()) << command.name << " left " << fmt::format("{}", fmt::join(left, ", "));
  }
}

}  // namespace
}  // namespace gazedirector
