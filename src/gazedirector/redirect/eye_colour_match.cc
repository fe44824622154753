#include "gazedirector/redirect/eye_colour_match.h"

#include <algorithm>
#include <cmath>

#include "gazedirector/redirect/eye_image.h"
#include "gazedirector/util/statistics.h"

namespace gazedirector {
namespace {

// The luminances of the colour samples (B, G, R) in `samples`[first..first + 2].
template <std::size_t N>
std::vector<double> Luminances(const std::array<std::vector<double>, N>& samples, int first) {
  std::vector<double> luminance(samples[first].size());
  for (std::size_t i = 0; i < luminance.size(); ++i) {
    luminance[i] = Luminance(cv::Vec3f(samples[first][i], samples[first + 1][i], samples[first + 2][i]));
  }
  return luminance;
}

}  // namespace

void EyeColourMatch::Add(const cv::Vec3f& photo, const cv::Vec3f& rendered, bool sclera) {
  if (!sclera) {
    for (int c = 0; c < 3; ++c) {
      iris_[c].push_back(photo[c]);
      iris_[3 + c].push_back(rendered[c]);
    }
    return;
  }
  for (int c = 0; c < 3; ++c) sclera_[c].push_back(photo[c]);
  sclera_[3].push_back(Luminance(rendered));
  sclera_[4].push_back(Luminance(photo));
}

void EyeColourMatch::Finish() {
  sclera_known_ = sclera_[3].size() >= kEnough;
  float photo_sclera = -1;  // the photo sclera's luminance
  if (sclera_known_) {
    for (int c = 0; c < 3; ++c) sclera_colour_[c] = static_cast<float>(Median(std::move(sclera_[c])));
    sclera_luminance_ = std::max(1e-3f, static_cast<float>(Median(std::move(sclera_[3]))));
    photo_sclera = static_cast<float>(Median(std::move(sclera_[4])));
    dark_sclera_ = 0.7f * photo_sclera;
  }
  FinishIris(photo_sclera);
  for (auto& samples : sclera_) samples = {};
  for (auto& samples : iris_) samples = {};
}

cv::Vec3f EyeColourMatch::Match(const cv::Vec3f& rendered, bool sclera, const cv::Vec3f& photo_sclera) const {
  if (sclera && sclera_known_) {
    // Half the rendering's contrast: its sclera darkens toward the
    // periphery, which real eyes, wet and lit from all around, hardly do.
    // Never brighter than the photo's sclera there, which has the real light.
    return photo_sclera * std::clamp(std::sqrt(Luminance(rendered) / sclera_luminance_), 0.7f, 1.0f);
  }
  if (!sclera && iris_matched_) {
    const float luminance = iris_photo_luminance_ + iris_contrast_ * (Luminance(rendered) - iris_rendered_luminance_);
    return iris_photo_ * std::max(0.0f, luminance / iris_photo_luminance_);
  }
  return rendered;  // too few samples to match
}

void EyeColourMatches::Finish() {
  both_.Finish();
  for (EyeColourMatch& eye : eyes_) eye.Finish();
  for (int eye = 0; eye < 2; ++eye) {
    const EyeColourMatch& other = eyes_[1 - eye];
    const float least = other.complete() ? kLeastDarkness * other.iris_darkness() : 0.0f;
    own_[eye] = eyes_[eye].complete() && eyes_[eye].iris_darkness() >= least;
  }
}

void EyeColourMatch::FinishIris(float photo_sclera) {
  if (iris_[0].size() < kEnough) return;
  const std::array<double, 3> photo = Quartiles(Luminances(iris_, 0));
  const std::array<double, 3> rendered = Quartiles(Luminances(iris_, 3));
  const float iris = static_cast<float>(photo[1]);
  if (photo_sclera > iris) {
    bright_iris_ = iris + kBrightIris * (photo_sclera - iris);
    iris_darkness_ = (photo_sclera - iris) / photo_sclera;
  }
  iris_matched_ = true;
  for (int c = 0; c < 3; ++c) iris_photo_[c] = static_cast<float>(Median(std::move(iris_[c])));
  iris_photo_luminance_ = std::max(1e-3f, Luminance(iris_photo_));
  iris_rendered_luminance_ = static_cast<float>(rendered[1]);
  iris_contrast_ =
      static_cast<float>(std::clamp((photo[2] - photo[0]) / std::max(rendered[2] - rendered[0], 1e-3), 0.1, 1.5));
}

}  // namespace gazedirector
