#include "gazedirector/redirect/composite_recipe.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

// d30.jpg as CV_32FC3 in [0, 1].
cv::Mat Photo() {
  cv::Mat photo;
  cv::imread(testing::DataPath("images/d30.jpg").string()).convertTo(photo, CV_32FC3, 1.0 / 255);
  return photo;
}

// A recipe over the whole of a working-size image of `size` that changes
// nothing: every pixel fetches itself, and an eyeball block in the middle
// takes all of its colour from the photo where it is.
CompositeRecipe Identity(cv::Size size) {
  CompositeRecipe recipe;
  recipe.region = cv::Rect(cv::Point(), size);
  recipe.skin_source.create(size, CV_32FC2);
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) recipe.skin_source.at<cv::Vec2f>(y, x) = cv::Vec2f(x, y);
  }
  recipe.eyeball_mask = cv::Mat(size, CV_8UC1, cv::Scalar(0));
  recipe.eyeball_mask(cv::Rect(size.width / 4, size.height / 4, size.width / 2, size.height / 2)).setTo(255);
  recipe.photo_source = recipe.skin_source.clone();
  recipe.photo_share = cv::Mat(size, CV_32F, cv::Scalar(1));
  recipe.highlight = cv::Mat(size, CV_32FC3, cv::Scalar::all(0));
  recipe.rest = cv::Mat(size, CV_32FC3, cv::Scalar::all(0));
  recipe.seam_alpha = cv::Mat(size, CV_32F, cv::Scalar(1));
  return recipe;
}

TEST(CompositeRecipeTest, ARecipeThatChangesNothingKeepsEveryPixelOfTheLargerPhoto) {
  const cv::Mat photo = Photo();
  const cv::Mat out = FollowRecipe(Identity(photo.size() / 3), photo, 3, 3);
  // Fetched at the photo's own size, not shrunk and enlarged again (a
  // quarter of a grey level allows for the positions' rounding).
  EXPECT_LT(cv::norm(out, photo, cv::NORM_INF), 1e-3);
}

TEST(CompositeRecipeTest, WarpedSkinMovesThePhotoByTheScaledShift) {
  const cv::Mat photo = Photo();
  CompositeRecipe recipe = Identity(photo.size() / 2);
  recipe.eyeball_mask.setTo(0);
  recipe.skin_source += cv::Scalar(3, -1);  // each pixel fetches from 3 right and 1 up
  const cv::Mat out = FollowRecipe(recipe, photo, 2, 2);
  const cv::Rect inside(20, 20, photo.cols - 40, photo.rows - 40);
  EXPECT_LT(cv::norm(out(inside), photo(inside + cv::Point(6, -2)), cv::NORM_INF), 1e-3);
}

TEST(CompositeRecipeTest, ARenderedEyeballFillsItsMaskAndTheRestIsKept) {
  const cv::Mat photo = Photo();
  CompositeRecipe recipe = Identity(photo.size() / 2);
  recipe.photo_share.setTo(0);
  recipe.rest.setTo(cv::Scalar(0.9f, 0.8f, 0.7f));
  const cv::Mat out = FollowRecipe(recipe, photo, 2, 2);
  const cv::Rect small_block = cv::boundingRect(recipe.eyeball_mask);
  const cv::Rect block(small_block.tl() * 2, small_block.size() * 2);
  const cv::Rect inner(block.x + 2, block.y + 2, block.width - 4, block.height - 4);
  const cv::Mat expected(inner.size(), CV_32FC3, cv::Scalar(0.9f, 0.8f, 0.7f));
  EXPECT_LT(cv::norm(out(inner), expected, cv::NORM_INF), 1e-5);
  cv::Mat outside(photo.size(), CV_8UC1, cv::Scalar(255));
  outside(block + cv::Size(2, 2) - cv::Point(1, 1)).setTo(0);
  EXPECT_LT(cv::norm(out, photo, cv::NORM_INF, outside), 1e-3);
}

// Relit sclera: the photo's share is multiplied by the recipe's gain,
// after its old reflections are taken off.
TEST(CompositeRecipeTest, ThePhotosShareIsRelitByTheRecipesGain) {
  const cv::Mat photo = Photo();
  CompositeRecipe recipe = Identity(photo.size() / 2);
  recipe.photo_gain = cv::Mat(recipe.region.size(), CV_32F, cv::Scalar(0.75f));
  recipe.highlight.setTo(cv::Scalar::all(0.05f));
  const cv::Mat out = FollowRecipe(recipe, photo, 2, 2);
  const cv::Rect small_block = cv::boundingRect(recipe.eyeball_mask);
  const cv::Rect inner(small_block.x * 2 + 2, small_block.y * 2 + 2, small_block.width * 2 - 4,
                       small_block.height * 2 - 4);
  cv::Mat expected = 0.75f * (photo(inner) - cv::Scalar::all(0.05f));
  expected = cv::max(expected, 0.0f);
  EXPECT_LT(cv::norm(out(inner), expected, cv::NORM_INF), 1e-3);
}

}  // namespace
}  // namespace gazedirector
