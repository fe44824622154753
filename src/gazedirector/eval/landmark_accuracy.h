#pragma once

#include <filesystem>
#include <vector>

#include "gazedirector/face/face_tracker.h"

namespace gazedirector {

// Landmark accuracy on hand-marked faces in dlib's XML format: the mean
// point-to-point error of the 68 landmarks divided by the distance between the
// outer eye corners (36, 45), as in the 300-W benchmark.
struct LandmarkAccuracy {
  int faces = 0;              // marked faces with all 68 points
  int detected = 0;           // of those, found by the full pipeline
  std::vector<double> given_box_errors;  // the predictor on the marked face box
  std::vector<double> pipeline_errors;   // detection + landmarks, per detected face
  double MeanGivenBox() const;
  double MedianGivenBox() const;
  double MeanPipeline() const;
  double MedianPipeline() const;
};

// With `turn_deg`, each photo and its marked points are first turned by that
// much (clockwise as shown) about the photo's centre, on a canvas that holds
// the whole turned photo: faces tilted in the image, as a leaning head or a
// camera held askew shows them. The marked box is then given at that roll.
LandmarkAccuracy EvaluateLandmarks(const std::filesystem::path& xml, FaceTracker& tracker,
                                   const LandmarkDetector& landmark_detector, double turn_deg = 0);

double NormalisedLandmarkError(const Landmarks68& predicted, const Landmarks68& truth);

}  // namespace gazedirector
