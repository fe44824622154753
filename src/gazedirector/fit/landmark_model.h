#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "gazedirector/face/face.h"
#include "gazedirector/geometry/camera.h"
#include "gazedirector/model/eye_region_model.h"

namespace gazedirector {

enum class LandmarkGroup { kEyelid, kBrow, kNose };

// One of dlib's landmarks as the model synthesises it: a fixed linear
// combination of the facial mesh's vertices (of one eye, or of both for the
// nose), projected to the image.
struct ModelLandmark {
  struct Term {
    int eye;
    int vertex;
    double weight;
  };
  int dlib_index;
  LandmarkGroup group;
  std::vector<Term> terms;
};

// The 24 landmarks the fit compares with the face tracker's: per eye the two
// corners and two points on each lid, the five brow points, and two points on
// the bridge of the nose. The lid and brow points sit where dlib puts them
// along the curve (a third and two thirds of the lid, evenly along the brow),
// measured by arc length on the mean shape.
class LandmarkModel {
 public:
  explicit LandmarkModel(const EyeRegionModel& model);

  const std::vector<ModelLandmark>& landmarks() const { return landmarks_; }

  // The landmarks of a posed model on the camera's image, in landmarks() order.
  void Project(const PosedModel& posed, const Camera& camera, std::vector<Eigen::Vector2d>& points) const;

  // Only the landmarks of one eye (and no nose), for fitting a single eye.
  LandmarkModel OneEye(int eye) const;
  // A single point, the mean of one eye's six landmarks (canthi and lids),
  // as a crop framed on those landmarks is centred: it moves with the lids.
  LandmarkModel EyeCentre(int eye) const;

 private:
  LandmarkModel() = default;
  std::vector<ModelLandmark> landmarks_;
};

}  // namespace gazedirector
