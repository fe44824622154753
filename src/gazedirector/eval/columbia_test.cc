#include "gazedirector/eval/columbia.h"

#include <gtest/gtest.h>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

ColumbiaCrop Crop(const std::string& name) {
  ColumbiaCrop crop;
  EXPECT_TRUE(ParseColumbiaName(name, crop)) << name;
  return crop;
}

TEST(ColumbiaTest, NamesGiveLabelsAndTheirPhoto) {
  const ColumbiaCrop crop = Crop("0012_2m_-15P_10V_-5H_R.jpg");
  EXPECT_EQ(crop.subject, "0012");
  EXPECT_EQ(crop.head_pose, -15);
  EXPECT_EQ(crop.vertical, 10);
  EXPECT_EQ(crop.horizontal, -5);
  EXPECT_EQ(crop.eye, 'R');
  EXPECT_EQ(crop.ModelEye(), kLeftEye);
  EXPECT_EQ(crop.Photo(), "0012_2m_-15P_10V_-5H");
  EXPECT_EQ(Crop("0012_2m_-15P_10V_-5H_L.jpg").Photo(), crop.Photo());
  ColumbiaCrop not_one;
  EXPECT_FALSE(ParseColumbiaName("0012_2m_-15P_10V_-5H.jpg", not_one));
  EXPECT_FALSE(ParseColumbiaName("d30.jpg", not_one));
}

TEST(ColumbiaTest, APhotosGazeIsTheMeanOfItsEyes) {
  std::vector<ColumbiaFit> fits(3);
  fits[0].crop = Crop("0001_2m_0P_0V_10H_L.jpg"), fits[0].pitch = 2, fits[0].yaw = 4;
  fits[1].crop = Crop("0001_2m_0P_-10V_0H_L.jpg"), fits[1].pitch = -7, fits[1].yaw = 1;
  fits[2].crop = Crop("0001_2m_0P_0V_10H_R.jpg"), fits[2].pitch = -1, fits[2].yaw = 14;
  const std::vector<ColumbiaPhoto> photos = CombineEyes(fits);
  ASSERT_EQ(photos.size(), 2u);
  EXPECT_EQ(photos[0].eyes, 2);
  EXPECT_DOUBLE_EQ(photos[0].pitch, 0.5);
  EXPECT_DOUBLE_EQ(photos[0].yaw, 9);
  EXPECT_DOUBLE_EQ(photos[0].yaw_error, 1);
  EXPECT_DOUBLE_EQ(photos[0].pitch_error, 0.5);
  EXPECT_EQ(photos[1].eyes, 1);  // its other eye's crop is missing
  EXPECT_DOUBLE_EQ(photos[1].pitch_error, 3);
  EXPECT_DOUBLE_EQ(photos[1].yaw_error, 1);
}

// Real crops: a subject looking 15 degrees either side of straight ahead,
// each eye fitted on its own, both eyes together within a few degrees.
TEST(ColumbiaTest, BothEyesOfARealFaceGiveItsHorizontalGaze) {
  std::vector<ColumbiaCrop> crops;
  for (const char* name : {"0003_2m_0P_0V_-15H_L.jpg", "0003_2m_0P_0V_-15H_R.jpg", "0003_2m_0P_0V_15H_L.jpg",
                           "0003_2m_0P_0V_15H_R.jpg"}) {
    crops.push_back(Crop(testing::DataPath(std::string("columbia-eyes/") + name).string()));
  }
  FitOptions options;
  options.work_width = 128;
  const auto model = EyeRegionModel::Load(testing::TestAssets());
  const std::vector<ColumbiaPhoto> photos = CombineEyes(FitColumbia(crops, model, options, 2, false));
  ASSERT_EQ(photos.size(), 2u);
  for (const ColumbiaPhoto& photo : photos) {
    EXPECT_EQ(photo.eyes, 2);
    EXPECT_LT(photo.yaw_error, 5.0) << photo.crop.Photo() << ": yaw " << photo.yaw;
    EXPECT_LT(photo.pitch_error, 8.0) << photo.crop.Photo() << ": pitch " << photo.pitch;
  }
}

}  // namespace
}  // namespace gazedirector
