#include "gazedirector/face/face_io.h"

#include <string>

#include <gtest/gtest.h>

#include "gazedirector/geometry/rotation.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

// OpenFace's names and order, so that its readers take our CSVs.
TEST(FaceIoTest, CsvColumnsAreOpenFaces) {
  const std::vector<std::string> columns = FaceCsvColumns();
  ASSERT_EQ(columns.size(), 11u + 2 * kNumLandmarks);
  const std::vector<std::string> head(columns.begin(), columns.begin() + 11);
  EXPECT_EQ(head, (std::vector<std::string>{"frame", "face_id", "timestamp", "confidence", "success", "pose_Tx", "pose_Ty",
                                            "pose_Tz", "pose_Rx", "pose_Ry", "pose_Rz"}));
  EXPECT_EQ(columns[11], "x_0");
  EXPECT_EQ(columns[11 + 67], "x_67");
  EXPECT_EQ(columns[11 + 68], "y_0");
  EXPECT_EQ(columns.back(), "y_67");
}

TEST(FaceIoTest, AFramesRowHoldsItsFaceOrSaysThereIsNone) {
  const std::vector<std::string> none = FaceCsvRow(7, 0.28, nullptr);
  ASSERT_EQ(none.size(), FaceCsvColumns().size());
  EXPECT_EQ(none[0], "7");
  EXPECT_EQ(none[1], "-1");
  EXPECT_EQ(none[2], "0.280");
  EXPECT_EQ(none[4], "0") << "success";

  const testing::DetectedStill still = testing::DetectStill("images/d30.jpg");
  ASSERT_EQ(still.faces.size(), 1u);
  const Face& face = still.faces.front();
  const std::vector<std::string> row = FaceCsvRow(3, 0.1, &face);
  ASSERT_EQ(row.size(), FaceCsvColumns().size());
  EXPECT_EQ(row[1], std::to_string(face.id));
  EXPECT_EQ(row[4], "1");
  EXPECT_NEAR(std::stod(row[7]), face.pose.translation.z(), 0.051) << "pose_Tz, mm";
  EXPECT_NEAR(std::stod(row[8]), EulerXYZFromRotation(face.pose.rotation).x(), 6e-5) << "pose_Rx, radians";
  for (int i = 0; i < kNumLandmarks; ++i) {
    EXPECT_NEAR(std::stod(row[11 + i]), face.landmarks[i].x(), 0.0051) << "x_" << i;
    EXPECT_NEAR(std::stod(row[11 + kNumLandmarks + i]), face.landmarks[i].y(), 0.0051) << "y_" << i;
  }
}

TEST(FaceIoTest, JsonCarriesTheLandmarksPoseAndCamera) {
  const testing::DetectedStill still = testing::DetectStill("images/d30.jpg");
  ASSERT_EQ(still.faces.size(), 1u);
  const Face& face = still.faces.front();
  const nlohmann::json json = ToJson(face);
  ASSERT_EQ(json.at("landmarks").size(), static_cast<std::size_t>(kNumLandmarks));
  EXPECT_NEAR(json["landmarks"][36][0].get<double>(), face.landmarks[36].x(), 6e-4);
  EXPECT_NEAR(json["confidence"].get<double>(), face.confidence, 6e-5);
  const nlohmann::json& rows = json.at("head_pose").at("rotation_matrix");
  Eigen::Matrix3d rotation;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) rotation(r, c) = rows[r][c].get<double>();
  }
  EXPECT_LT((rotation - face.pose.rotation).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-5);

  const Camera camera = CameraFromJson(ToJson(still.camera));
  EXPECT_EQ(camera.fx, still.camera.fx);
  EXPECT_EQ(camera.cy, still.camera.cy);
  EXPECT_EQ(camera.width, still.camera.width);
  EXPECT_EQ(camera.height, still.camera.height);
}

}  // namespace
}  // namespace gazedirector
