#include "gazedirector/io/fit_io.h"

#include <fstream>

#include <gtest/gtest.h>

#include "gazedirector/util/error.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

FaceFit SomeFit(int id) {
  FaceFit fit;
  fit.face.id = id;
  fit.face.confidence = 0.9;
  fit.fit.phi.block<Block::kTranslation>() = Eigen::Vector3d(10, -5, 550);
  fit.fit.phi.gaze_pitch() = -7.25;
  fit.fit.phi.gaze_yaw() = 13.5;
  fit.fit.phi.shape()[3] = 0.75;
  fit.fit.good = id % 2 == 0;
  fit.fit.note = fit.fit.good ? "" : "the eyes do not match";
  fit.eyes_closed = id == 1;
  return fit;
}

TEST(FitIoTest, FitsWrittenAsJsonLinesReadBack) {
  const auto path = testing::ScratchDir("fit_io") / "fits.jsonl";
  const Camera camera = Camera::Default(512, 512);
  {
    std::ofstream out(path);
    out << FrameRecord(0, 0.0, {SomeFit(0), SomeFit(1)}, &camera).dump() << '\n';
    out << FrameRecord(1, 1 / 30.0, {}).dump() << '\n';
    out << FrameRecord(2, 2 / 30.0, {SomeFit(0)}).dump() << '\n';
  }
  const FitsFile file = ReadFits(path);
  ASSERT_TRUE(file.camera.has_value());
  EXPECT_EQ(file.camera->width, 512);
  ASSERT_EQ(file.frames.size(), 3u);
  const StoredFrame& first = file.frames.at(0);
  ASSERT_EQ(first.faces.size(), 2u);
  EXPECT_EQ(first.faces[1].face_id, 1);
  EXPECT_FALSE(first.faces[1].good);
  EXPECT_EQ(first.faces[1].note, "the eyes do not match");
  EXPECT_TRUE(first.faces[1].eyes_closed);
  EXPECT_FALSE(first.faces[0].eyes_closed);
  EXPECT_NEAR(first.faces[0].phi.gaze_pitch(), -7.25, 1e-9);
  EXPECT_NEAR(first.faces[0].phi.shape()[3], 0.75, 1e-9);
  EXPECT_TRUE(file.frames.at(1).faces.empty());
  EXPECT_NEAR(file.frames.at(2).timestamp_s, 2 / 30.0, 1e-3);
}

TEST(FitIoTest, CsvRowsMatchTheOpenFaceColumns) {
  const FaceFit fit = SomeFit(0);
  EXPECT_EQ(FitCsvRow(3, 0.1, &fit).size(), FitCsvColumns().size());
  EXPECT_EQ(FitCsvRow(3, 0.1, nullptr).size(), FitCsvColumns().size());
  const auto columns = FitCsvColumns();
  for (const char* name : {"gaze_0_x", "gaze_1_z", "gaze_angle_x", "gaze_angle_y", "pose_Rx", "AU45_c"}) {
    EXPECT_NE(std::find(columns.begin(), columns.end(), name), columns.end()) << name;
  }
  const FaceFit blinking = SomeFit(1);
  const auto blink_column = std::find(columns.begin(), columns.end(), "AU45_c") - columns.begin();
  EXPECT_EQ(FitCsvRow(3, 0.1, &fit)[blink_column], "0");
  EXPECT_EQ(FitCsvRow(3, 0.1, &blinking)[blink_column], "1");
}

// The message of the input error reading `path` fails with ("" and a test
// failure when it reads, or fails otherwise).
std::string BadInputMessage(const std::filesystem::path& path) {
  try {
    ReadFits(path);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::kBadInput);
    return e.what();
  }
  ADD_FAILURE() << "expected an error reading " << path;
  return "";
}

TEST(FitIoTest, BrokenFilesFailWithTheLine) {
  const auto path = testing::ScratchDir("fit_io_bad") / "fits.jsonl";
  {
    std::ofstream out(path);
    out << FrameRecord(0, 0.0, {SomeFit(0)}).dump() << "\n{not json\n";
  }
  const std::string not_json = BadInputMessage(path);
  EXPECT_NE(not_json.find(":2:"), std::string::npos) << not_json;
  EXPECT_THROW(ReadFits(path.parent_path() / "missing.jsonl"), Error);
  {
    // An edit that puts the eyes behind the camera names the file and the record.
    nlohmann::json record = FrameRecord(0, 0.0, {SomeFit(0)});
    record["faces"][0]["parameters"]["translation_mm"] = {0, 0, -100};
    std::ofstream(path) << FrameRecord(1, 0.04, {SomeFit(0)}).dump() << "\n" << record.dump() << "\n";
  }
  const std::string behind = BadInputMessage(path);
  EXPECT_NE(behind.find("fits.jsonl: record 2: translation_mm"), std::string::npos) << behind;
}

}  // namespace
}  // namespace gazedirector
