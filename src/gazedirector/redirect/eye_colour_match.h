#pragma once

#include <array>
#include <vector>

#include <opencv2/core.hpp>

namespace gazedirector {

// The rendering's colours matched to the photo's eye, from samples where
// both are known, separately for the iris (the cornea, which shows it) and
// the sclera: medians, which the few skin pixels a slightly wide fit lets in
// cannot tint. The rendered iris takes the photo iris's median colour, its
// brightness varying as the rendering's at the photo's contrast: a dark, even
// iris must not show the iris texture's brighter ring, nor a grey one the
// texture's hues.
class EyeColourMatch {
 public:
  // The photo's colour `photo` (BGR) where the rendering shows `rendered`.
  void Add(const cv::Vec3f& photo, const cv::Vec3f& rendered, bool sclera);
  // After the last Add: computes the match and lets the samples go.
  void Finish();

  // Photo sclera darker than this is lashes, the iris's edge where the fit
  // missed it by a pixel, or shadow under a lid (-1 when unknown).
  float dark_sclera() const { return dark_sclera_; }
  // Photo "iris" brighter than this is sclera beside an iris the fit
  // placed off the photo's: moved with the iris, it would draw a white
  // crescent inside the new one (-1 when unknown).
  float bright_iris() const { return bright_iris_; }

  // The photo's typical sclera colour (meaningful once sclera_known()).
  bool sclera_known() const { return sclera_known_; }
  // Both the iris and the sclera had enough samples.
  bool complete() const { return sclera_known_ && iris_matched_; }
  // How much darker the photo's iris is than its sclera, as a share of the
  // sclera's luminance (0 where unknown or not darker).
  float iris_darkness() const { return iris_darkness_; }
  const cv::Vec3f& sclera_colour() const { return sclera_colour_; }

  // A rendered colour as the photo's eye would show it. Sclera takes the
  // colour of the photo's own sclera nearby (`photo_sclera`, see
  // NearbyColour), shaded as rendered: the texture's reddish periphery, which
  // a large turn brings into view, would read as smudged skin, and one colour
  // for the whole sclera as a pale band where a lid moved.
  cv::Vec3f Match(const cv::Vec3f& rendered, bool sclera, const cv::Vec3f& photo_sclera) const;

 private:
  // The bright-iris threshold (none where the sclera is unknown: -1), and
  // the photo iris's median colour and luminance spread, which the rendered iris takes.
  void FinishIris(float photo_sclera);

  static constexpr std::size_t kEnough = 10;  // samples
  std::array<std::vector<double>, 5> sclera_;  // the photo's sclera (B, G, R), the rendering's luminance there, the photo's
  bool sclera_known_ = false;
  cv::Vec3f sclera_colour_;
  float sclera_luminance_ = 1;
  float dark_sclera_ = -1;
  static constexpr float kBrightIris = 0.6f;  // of the way from the photo's iris to its sclera
  std::array<std::vector<double>, 6> iris_;  // the photo's iris (B, G, R) and the rendering's there
  bool iris_matched_ = false;
  cv::Vec3f iris_photo_;  // the photo's median iris
  float iris_photo_luminance_ = 1, iris_rendered_luminance_ = 0;
  float iris_contrast_ = 1;  // the ratio of their luminances' spreads
  float bright_iris_ = -1;
  float iris_darkness_ = 0;
};

// One match per eye: each eye has its own light (one behind a tinted lens or
// in a shadow), and thresholds and colours read from both would suit neither
// (d8.jpg: his lit eye's pale iris, held against both eyes' colours, was
// taken for sclera and rendered in the shaded eye's dark blue). An eye that
// shows too little of its iris or sclera takes the match of both, and so does
// one whose iris stands out from its sclera less than a quarter as much as the
// other eye's does: its fit is off, so its "iris" is mostly sclera (d14.mp4's
// far glances) or its "sclera" the lashes' shade, and the other eye's samples
// are what tells them apart.
class EyeColourMatches {
 public:
  void Add(int eye, const cv::Vec3f& photo, const cv::Vec3f& rendered, bool sclera) {
    eyes_[eye].Add(photo, rendered, sclera);
    both_.Add(photo, rendered, sclera);
  }
  void Finish();

  const EyeColourMatch& operator[](int eye) const { return own_[eye] ? eyes_[eye] : both_; }
  const EyeColourMatch& both() const { return both_; }

 private:
  std::array<EyeColourMatch, 2> eyes_;
  EyeColourMatch both_;
  static constexpr float kLeastDarkness = 0.25f;  // of the other eye's iris_darkness()
  std::array<bool, 2> own_ = {false, false};
};

}  // namespace gazedirector
