#include "gazedirector/eval/redirect_columbia.h"

#include <gtest/gtest.h>

#include "gazedirector/io/image_io.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

cv::Mat Crop(const std::string& name) { return ReadImage(testing::DataPath("columbia-eyes/" + name)); }

// The eye opening and lids of subject 0007's left-eye crops.
const cv::Rect kEye(6, 18, 52, 26);

TEST(RedirectColumbiaTest, RegistrationRecoversAKnownShiftDespiteADifferentGaze) {
  const cv::Mat source = Crop("0007_2m_0P_0V_0H_L.jpg");
  // The skin of the source crop around the eye of another gaze, moved by a known amount.
  cv::Mat other = source.clone();
  Crop("0007_2m_0P_0V_15H_L.jpg")(kEye).copyTo(other(kEye));
  const cv::Point2f shift(1.5f, -2.25f);
  const cv::Mat moved = Shifted(other, shift);
  // (The pasted eye's edges move with it: they are kept out too.)
  const cv::Point2f found = RegisterOnSkin(source, moved, kEye + cv::Size(6, 6) - cv::Point(3, 3));
  EXPECT_NEAR(found.x, shift.x, 0.15);
  EXPECT_NEAR(found.y, shift.y, 0.15);
  // Moving the source by the estimate makes it match.
  EXPECT_LT(MeanAbsoluteError(Shifted(source, found), moved), 0.5 * MeanAbsoluteError(source, moved));
}

TEST(RedirectColumbiaTest, CropsOfALowerGazeAreFramedLower) {
  // Columbia's crops are centred on each photo's eye landmarks, which drop with
  // the lids when the eyes look down: the skin moves up in the crop.
  const cv::Mat source = Crop("0007_2m_0P_0V_0H_L.jpg");
  const cv::Mat down = Crop("0007_2m_0P_-10V_0H_L.jpg");
  const cv::Point2f shift = RegisterOnSkin(source, down, kEye);
  EXPECT_LT(shift.y, -1.0);
  EXPECT_LT(MeanAbsoluteError(Shifted(source, shift), down), MeanAbsoluteError(source, down));
}

TEST(RedirectColumbiaTest, ANoShiftLeavesTheImageAlone) {
  const cv::Mat source = Crop("0007_2m_0P_0V_0H_L.jpg");
  EXPECT_EQ(MeanAbsoluteError(Shifted(source, {0, 0}), source), 0.0);
  EXPECT_NEAR(RegisterOnSkin(source, source, kEye).x, 0.0, 0.01);
}

}  // namespace
}  // namespace gazedirector
