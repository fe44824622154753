#include "gazedirector/face/mean_face.h"

#include <fstream>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "gazedirector/io/assets.h"
#include "gazedirector/util/error.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;

// The asset's points turned into the head frame: x toward the subject's
// left, y down, z into the head, millimetres.
TEST(MeanFaceTest, TheAssetIsAFaceInTheHeadFrame) {
  const MeanFace face = LoadMeanFace(testing::TestAssets().mean_face());
  const Eigen::Vector3d right_outer = face[36], left_outer = face[45], nose_tip = face[30], chin = face[8];
  EXPECT_GT(left_outer.x(), right_outer.x()) << "x toward the subject's left";
  EXPECT_GT(chin.y(), right_outer.y() + 80) << "y down, the chin well below the eyes";
  for (int i = 0; i < kNumLandmarks; ++i) {
    if (i == 30) continue;
    EXPECT_GT(face[i].z(), nose_tip.z()) << "the nose tip nearest the viewer; point " << i;
  }
  EXPECT_NEAR((left_outer - right_outer).norm(), 89.2, 1.0) << "the outer eye corners, mm";
  // Mirror pairs of the 68-point scheme: jaw ends, eye corners, mouth corners.
  for (const auto& [a, b] : {std::pair{0, 16}, {36, 45}, {39, 42}, {48, 54}}) {
    EXPECT_NEAR(face[a].x(), -face[b].x(), 1.0) << a << " and " << b;
    EXPECT_NEAR(face[a].y(), face[b].y(), 1.0) << a << " and " << b;
    EXPECT_NEAR(face[a].z(), face[b].z(), 1.0) << a << " and " << b;
  }
}

// A broken asset gets the assets' exit code and names the file, whatever
// is wrong with it (not an internal error from the JSON library).
TEST(MeanFaceTest, ABrokenFileFailsWithTheAssetsCode) {
  std::string points;
  for (int i = 0; i < kNumLandmarks - 1; ++i) points += "[0, 0, 0], ";
  const struct {
    std::string name, text, says;
  } cases[] = {
      {"not_json", "{\"points\": [", "invalid JSON"},
      {"no_points", "{\"units\": \"mm\"}", "not a mean face"},
      {"too_few", "{\"points\": [" + points.substr(0, points.size() - 2) + "]}", "expected 68 points"},
      {"short_point", "{\"points\": [" + points + "[1, 2]]}", "point 67 is not x, y, z"},
      {"word", "{\"points\": [" + points + "[1, 2, \"three\"]]}", "not a mean face"},
  };
  const fs::path dir = testing::ScratchDir("mean_face_broken");
  for (const auto& c : cases) {
    const fs::path path = dir / (c.name + ".json");
    std::ofstream(path) << c.text;
    try {
      LoadMeanFace(path);
      ADD_FAILURE() << c.name << ": loaded";
    } catch (const Error& error) {
      EXPECT_EQ(error.code(), ExitCode::kAssets) << c.name;
      const std::string message = error.what();
      EXPECT_NE(message.find(path.string()), std::string::npos) << message;
      EXPECT_NE(message.find(c.says), std::string::npos) << c.name << ": " << message;
    }
  }
}

}  // namespace
}  // namespace gazedirector
