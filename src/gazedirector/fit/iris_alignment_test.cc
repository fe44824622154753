#include "gazedirector/fit/iris_alignment.h"

#include <cmath>

#include <gtest/gtest.h>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

// d30.jpg: a fresh fit sits on both irises; the same fit with its gaze turned
// 35 degrees away has lost them, and the measure says so.
TEST(IrisAlignmentTest, ReadsAFitOnItsIrisesAndOneThatLostThem) {
  const testing::FittedStill& still = testing::FitStill("images/d30.jpg");
  Renderer renderer(testing::SharedModel());
  const std::array<double, 2> fitted =
      IrisMisalignment(still.image, still.camera, still.fit.phi, {true, true}, renderer);
  Parameters turned = still.fit.phi;
  turned.gaze_yaw() -= 35;
  const std::array<double, 2> lost = IrisMisalignment(still.image, still.camera, turned, {true, true}, renderer);
  for (int eye = 0; eye < 2; ++eye) {
    EXPECT_LT(fitted[eye], 0.45) << eye;  // 0.29, 0.37
    EXPECT_GT(lost[eye], 0.9) << eye;  // 1.15, 1.24
  }
  const std::array<double, 2> one = IrisMisalignment(still.image, still.camera, still.fit.phi, {false, true}, renderer);
  EXPECT_TRUE(std::isnan(one[kLeftEye]));
  EXPECT_NEAR(one[kRightEye], fitted[kRightEye], 0.05);
}

}  // namespace
}  // namespace gazedirector
