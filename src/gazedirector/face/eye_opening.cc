#include "gazedirector/face/eye_opening.h"

#include <algorithm>

namespace gazedirector {

double EyeAspectRatio(const Landmarks68& landmarks, int eye) {
  const int first = eye == 0 ? 36 : 42;
  const auto point = [&](int k) { return landmarks[first + k]; };
  const double width = (point(3) - point(0)).norm();
  if (width <= 0) return 0;
  return ((point(1) - point(5)).norm() + (point(2) - point(4)).norm()) / (2 * width);
}

double SmallerEyeAspectRatio(const Landmarks68& landmarks) {
  return std::min(EyeAspectRatio(landmarks, 0), EyeAspectRatio(landmarks, 1));
}

double EyeOpeningTracker::Update(double aspect_ratio) {
  // Rising at once and sinking by 2% a frame, the envelope forgets a blink's
  // few frames but follows eyes that stay narrowed for a second or more.
  constexpr double kSink = 0.02;
  usual_ = usual_ <= 0 || aspect_ratio > usual_ ? aspect_ratio : usual_ + kSink * (aspect_ratio - usual_);
  return usual_ > 0 ? aspect_ratio / usual_ : 1.0;
}

}  // namespace gazedirector
