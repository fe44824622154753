#pragma once

#include "gazedirector/face/face.h"

namespace gazedirector {

// How open an eye is by its six landmarks (36-41 or 42-47): the eye aspect
// ratio of Soukupová and Čech (2016), the mean of the two lid-to-lid heights
// over the corner-to-corner width. About 0.3 for an open eye, under 0.1 for a
// closed one; `eye` is 0 for the image-left eye (landmarks 36-41), 1 for the other.
double EyeAspectRatio(const Landmarks68& landmarks, int eye);

// The less open of the two eyes.
double SmallerEyeAspectRatio(const Landmarks68& landmarks);

// Follows how open a face's eyes usually are over a video, so that a blink
// is told apart from eyes that are small or narrowed for a while: an upper
// envelope that rises at once with the eyes and sinks slowly.
class EyeOpeningTracker {
 public:
  // Adds a frame's eye aspect ratio; returns its fraction of the usual one (1 on the first frame).
  double Update(double aspect_ratio);
  double usual() const { return usual_; }

 private:
  double usual_ = 0;
};

}  // namespace gazedirector
