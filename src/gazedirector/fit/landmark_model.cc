#include "gazedirector/fit/landmark_model.h"

#include <algorithm>

#include "gazedirector/model/eye_region_topology.h"

namespace gazedirector {
namespace {

using Terms = std::vector<ModelLandmark::Term>;

// A curve through weighted vertex combinations; Point(f) is the combination
// at fraction f of its arc length, measured on `shape`.
struct Curve {
  std::vector<Terms> points;

  Terms At(double fraction, const Eigen::Matrix3Xd& shape) const {
    std::vector<Eigen::Vector3d> positions;
    for (const Terms& point : points) {
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      for (const auto& term : point) p += term.weight * shape.col(term.vertex);
      positions.push_back(p);
    }
    std::vector<double> length = {0.0};
    for (std::size_t i = 1; i < positions.size(); ++i) length.push_back(length.back() + (positions[i] - positions[i - 1]).norm());
    const double target = std::clamp(fraction, 0.0, 1.0) * length.back();
    std::size_t segment = 1;
    while (segment + 1 < positions.size() && length[segment] < target) ++segment;
    const double span = length[segment] - length[segment - 1];
    const double t = span > 0 ? (target - length[segment - 1]) / span : 0.0;
    Terms result;
    for (const auto& term : points[segment - 1]) result.push_back({term.eye, term.vertex, (1 - t) * term.weight});
    for (const auto& term : points[segment]) result.push_back({term.eye, term.vertex, t * term.weight});
    return result;
  }
};

Terms InnerCanthus(int eye) {
  return {{eye, topology::kInnerCanthusA, 1 - topology::kInnerCanthusWeightB},
          {eye, topology::kInnerCanthusB, topology::kInnerCanthusWeightB}};
}

Curve VertexCurve(const std::vector<int>& vertices, int eye) {
  Curve curve;
  for (int v : vertices) curve.points.push_back({{eye, v, 1.0}});
  return curve;
}

}  // namespace

LandmarkModel::LandmarkModel(const EyeRegionModel& model) {
  const Eigen::Matrix3Xd& mean = model.shape_model().mean();
  // dlib's indices per eye: corners, lid points from the inner corner, brow from the inner end.
  struct EyeIndices {
    int inner, outer;
    int upper[2];  // at a third and two thirds from the inner corner
    int lower[2];
    int brow[5];   // inner end to outer end
  };
  const EyeIndices indices[2] = {
      {42, 45, {43, 44}, {47, 46}, {22, 23, 24, 25, 26}},  // the subject's left eye
      {39, 36, {38, 37}, {40, 41}, {21, 20, 19, 18, 17}},  // the subject's right eye
  };
  for (int eye = 0; eye < 2; ++eye) {
    const EyeIndices& dlib = indices[eye];
    landmarks_.push_back({dlib.inner, LandmarkGroup::kEyelid, InnerCanthus(eye)});
    landmarks_.push_back({dlib.outer, LandmarkGroup::kEyelid, {{eye, topology::kOuterCanthus, 1.0}}});
    // The visible rim of the opening (loop L0, around the caruncle): columns
    // 0-10 run along the upper lid, 10-19 and back to 0 along the lower.
    const auto& rim = topology::kLoops[0];
    std::vector<int> upper(rim.begin(), rim.begin() + topology::kOuterCornerColumn + 1);
    std::vector<int> lower = {rim[0]};
    for (int c = topology::kLoopColumns - 1; c >= topology::kOuterCornerColumn; --c) lower.push_back(rim[c]);
    for (int k = 0; k < 2; ++k) {
      landmarks_.push_back({dlib.upper[k], LandmarkGroup::kEyelid, VertexCurve(upper, eye).At((k + 1) / 3.0, mean)});
      landmarks_.push_back({dlib.lower[k], LandmarkGroup::kEyelid, VertexCurve(lower, eye).At((k + 1) / 3.0, mean)});
    }
    Curve brow;
    for (std::size_t k = 0; k < topology::kBrowA.size(); ++k) {
      brow.points.push_back({{eye, topology::kBrowA[k], 1.0 - topology::kBrowWeight[k]},
                             {eye, topology::kBrowB[k], topology::kBrowWeight[k]}});
    }
    for (int k = 0; k < 5; ++k) landmarks_.push_back({dlib.brow[k], LandmarkGroup::kBrow, brow.At(k / 4.0, mean)});
  }
  // The bridge of the nose lies on the midline where the two regions meet:
  // 27 about 4 mm above the eye line, 28 about 7 mm below it.
  constexpr int kNoseTop = 198, kNoseLowA = 200, kNoseLowB = 201;
  landmarks_.push_back({27, LandmarkGroup::kNose, {{kLeftEye, kNoseTop, 0.5}, {kRightEye, kNoseTop, 0.5}}});
  landmarks_.push_back({28, LandmarkGroup::kNose,
                        {{kLeftEye, kNoseLowA, 0.275}, {kLeftEye, kNoseLowB, 0.225},
                         {kRightEye, kNoseLowA, 0.275}, {kRightEye, kNoseLowB, 0.225}}});
}

void LandmarkModel::Project(const PosedModel& posed, const Camera& camera, std::vector<Eigen::Vector2d>& points) const {
  points.resize(landmarks_.size());
  for (std::size_t i = 0; i < landmarks_.size(); ++i) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (const auto& term : landmarks_[i].terms) {
      const PosedEye& eye = posed.eyes[term.eye];
      p += term.weight * (eye.region_to_camera * posed.region[term.eye].col(term.vertex) + eye.centre);
    }
    points[i] = camera.Project(p);
  }
}

LandmarkModel LandmarkModel::EyeCentre(int eye) const {
  ModelLandmark centre{-1, LandmarkGroup::kEyelid, {}};
  int count = 0;
  for (const ModelLandmark& landmark : landmarks_) {
    if (landmark.group != LandmarkGroup::kEyelid || landmark.terms.front().eye != eye) continue;
    centre.terms.insert(centre.terms.end(), landmark.terms.begin(), landmark.terms.end());
    ++count;
  }
  for (auto& term : centre.terms) term.weight /= count;
  LandmarkModel result;
  result.landmarks_.push_back(centre);
  return result;
}

LandmarkModel LandmarkModel::OneEye(int eye) const {
  LandmarkModel subset;
  for (const ModelLandmark& landmark : landmarks_) {
    if (landmark.group != LandmarkGroup::kNose && landmark.terms.front().eye == eye) subset.landmarks_.push_back(landmark);
  }
  return subset;
}

}  // namespace gazedirector
