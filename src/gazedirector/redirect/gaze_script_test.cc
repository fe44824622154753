#include "gazedirector/redirect/gaze_script.h"

#include <gtest/gtest.h>

#include "gazedirector/util/error.h"

namespace gazedirector {
namespace {

GazeScript Script() {
  return GazeScript::FromJson(nlohmann::json::parse(R"({
    "transition_s": 0.4,
    "segments": [{"start_s": 0, "target": "camera"},
                 {"start_s": 3, "target": {"gaze": [0, 25], "frame": "head"}},
                 {"start_s": 5, "reading": {"width_deg": 20, "line_s": 1.0, "lines": 3, "line_spacing_deg": 4, "pitch_deg": -6}}]})"));
}

Parameters Fitted() {
  Parameters phi;
  phi.block<Block::kTranslation>() = Eigen::Vector3d(0, 0, 600);
  return phi;
}

TEST(GazeScriptTest, HoldsEachTargetAndEasesBetweenThem) {
  const GazeScript script = Script();
  const Parameters fitted = Fitted();
  EXPECT_NEAR(script.TargetAt(fitted, 1.0).gaze_yaw(), 0.0, 1e-9);   // the camera, straight ahead
  EXPECT_NEAR(script.TargetAt(fitted, 4.0).gaze_yaw(), 25.0, 1e-9);  // after the transition
  const double midway = script.TargetAt(fitted, 3.2).gaze_yaw();
  EXPECT_GT(midway, 5.0);
  EXPECT_LT(midway, 20.0);
  // No jumps: 10 ms apart, the gaze moves a little.
  for (double t = 0; t < 8; t += 0.05) {
    EXPECT_LT(std::abs(script.TargetAt(fitted, t + 0.01).gaze_yaw() - script.TargetAt(fitted, t).gaze_yaw()), 3.0) << t;
  }
}

TEST(GazeScriptTest, ListsWhenEachSegmentStarts) {
  EXPECT_EQ(Script().StartTimes(), (std::vector<double>{0, 3, 5}));
  EXPECT_EQ(GazeScript::Constant(GazeTarget::Camera()).StartTimes(), (std::vector<double>{0}));
}

TEST(GazeScriptTest, ReadingSweepsAlongLinesMovingDown) {
  const GazeScript script = Script();
  const Parameters fitted = Fitted();
  // Within a line the yaw goes from the subject's left (+) to the right (-).
  const double start = script.TargetAt(fitted, 5.45).gaze_yaw(), end = script.TargetAt(fitted, 5.95).gaze_yaw();
  EXPECT_GT(start, end + 5);
  // Each line lower than the last.
  const double line1 = script.TargetAt(fitted, 5.8).gaze_pitch(), line2 = script.TargetAt(fitted, 7.0).gaze_pitch();
  EXPECT_NEAR(line1 - line2, 4.0, 1e-9);
}

TEST(GazeScriptTest, RejectsBadScripts) {
  EXPECT_THROW(GazeScript::FromJson(nlohmann::json::parse(R"({"segments": []})")), Error);
  EXPECT_THROW(GazeScript::FromJson(nlohmann::json::parse(R"({"segments": [{"start_s": 2, "target": "camera"}, {"start_s": 1, "target": "camera"}]})")), Error);
  EXPECT_THROW(GazeScript::FromJson(nlohmann::json::parse(R"({"segments": [{"start_s": 0}]})")), Error);
  EXPECT_THROW(GazeScript::FromJson(nlohmann::json::parse(R"({"segments": [{"reading": {"width_deg": 400}}]})")), Error);
  EXPECT_THROW(GazeScript::FromJson(nlohmann::json::parse(R"({"segments": [{"reading": {"lines": 30, "line_spacing_deg": 10}}]})")), Error);
  EXPECT_THROW(GazeScript::FromJson(nlohmann::json::parse(R"({"segments": [{"target": {"gaze": [0, 135]}}]})")), Error);
}

// Values of the wrong JSON type get the script's own one-line errors, not the JSON library's.
TEST(GazeScriptTest, NamesWhatIsOfTheWrongType) {
  auto error_of = [](const char* text) -> std::string {
    try {
      GazeScript::FromJson(nlohmann::json::parse(text));
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error_of("[1, 2]"), "a gaze script is a JSON object with a \"segments\" list");
  EXPECT_EQ(error_of(R"({"segments": [3]})"), "each segment is a JSON object, not 3");
  EXPECT_EQ(error_of(R"({"segments": [{"start_s": "2", "target": "camera"}]})"), "\"start_s\" must be a number, not \"2\"");
  EXPECT_EQ(error_of(R"({"transition_s": null, "segments": [{"target": "camera"}]})"),
            "\"transition_s\" must be a number, not null");
  EXPECT_EQ(error_of(R"({"segments": [{"reading": {"lines": 2.5}}]})"), "\"lines\" must be a whole number, not 2.5");
  EXPECT_EQ(error_of(R"({"segments": [{"reading": []}]})"), "reading: a JSON object, not []");
}

}  // namespace
}  // namespace gazedirector
