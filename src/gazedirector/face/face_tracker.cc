#include "gazedirector/face/face_tracker.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <span>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include "gazedirector/face/head_pose.h"
#include "gazedirector/face/turned_crop.h"
#include "gazedirector/geometry/rotation.h"

namespace gazedirector {
namespace {

Eigen::Vector2d Centroid(const Landmarks68& landmarks) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const auto& p : landmarks) sum += p;
  return sum / kNumLandmarks;
}

double Spread(const Landmarks68& landmarks, const Eigen::Vector2d& centroid) {
  double squared = 0;
  for (const auto& p : landmarks) squared += (p - centroid).squaredNorm();
  return std::sqrt(squared / kNumLandmarks);
}

cv::Mat ToGray(const cv::Mat& bgr, cv::Mat& gray) {
  if (bgr.channels() == 1) return bgr;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  return gray;
}

// A still photo with no face above HOG's usual threshold (0) takes its best
// window down to this score (see DetectFaces).
constexpr double kFallbackThreshold = -0.6;

// Faces whose landmarks show them tilted less than this are landmarked as
// they stand in the image (the predictor was trained on such faces); others in
// a crop turned upright to them.
constexpr double kUprightRoll = DegToRad(15.0);
// Landmarks are predicted again when they show a tilt this far from the one
// they were predicted at.
constexpr double kRollTolerance = DegToRad(5.0);
// HOG finds faces within about 30 degrees of upright, so searches 45 degrees
// apart cover every tilt. Faces upside down are rare (a phone held so marks
// its picture): those searches run only where the others found nothing.
constexpr std::array<double, 4> kTiltedRolls = {DegToRad(45.0), DegToRad(-45.0), DegToRad(90.0), DegToRad(-90.0)};
constexpr std::array<double, 3> kUpsideDownRolls = {DegToRad(135.0), DegToRad(-135.0), DegToRad(180.0)};

// Two detections of one face, or of a face and a part of it (a nose and its
// nostrils turned a quarter look like a small face): they overlap, or one
// lies mostly inside the other.
bool SameFace(const cv::Rect2d& a, const cv::Rect2d& b) {
  const double inside = (a & b).area() / std::max(std::min(a.area(), b.area()), 1e-9);
  return IntersectionOverUnion(a, b) > 0.3 || inside > 0.5;
}

// Adds a detection from another search of the same image, or keeps the
// better-scoring of it and the one already found for that face.
void MergeDetection(std::vector<Detection>& found, const Detection& detection) {
  auto same = std::find_if(found.begin(), found.end(), [&](const Detection& f) { return SameFace(f.box, detection.box); });
  if (same == found.end()) {
    found.push_back(detection);
  } else if (detection.score > same->score) {
    *same = detection;
  }
}

double PredictionRoll(double shown_roll) { return std::abs(shown_roll) < kUprightRoll ? 0.0 : shown_roll; }

}  // namespace

double StillDetectionScale(int width, int height) {
  return std::clamp(2000.0 / std::max(width, height), 0.25, 2.0);
}

double VideoDetectionScale(int width, int height) {
  return std::clamp(800.0 / std::max(width, height), 0.25, 1.0);
}

FaceTracker::FaceTracker(std::shared_ptr<const LandmarkDetector> landmark_detector, MeanFace mean_face,
                         FaceTrackerOptions options)
    : landmark_detector_(std::move(landmark_detector)), mean_face_(mean_face), options_(options) {}

void FaceTracker::Reset() {
  tracks_.clear();
  frames_since_search_ = 0;
  frames_since_turned_search_ = -1;
}

FaceTracker::BoxCalibration FaceTracker::Calibrate(const cv::Rect2d& box, double roll, const Landmarks68& landmarks) {
  const Eigen::Vector2d centroid = Centroid(landmarks);
  const double spread = std::max(Spread(landmarks, centroid), 1e-6);
  const Eigen::Vector2d box_centre(box.x + 0.5 * box.width, box.y + 0.5 * box.height);
  return {Eigen::Rotation2Dd(-roll) * ((box_centre - centroid) / spread), box.width / spread};
}

cv::Rect2d FaceTracker::BoxFromLandmarks(const Landmarks68& landmarks, const BoxCalibration& calibration, double roll) {
  const Eigen::Vector2d centroid = Centroid(landmarks);
  const double spread = Spread(landmarks, centroid);
  const Eigen::Vector2d centre = centroid + spread * (Eigen::Rotation2Dd(roll) * calibration.offset);
  const double side = spread * calibration.size;
  return {centre.x() - 0.5 * side, centre.y() - 0.5 * side, side, side};
}

Landmarks68 FaceTracker::FindLandmarks(const cv::Mat& gray, cv::Rect2d& box, double& roll) const {
  // Where HOG's box sits relative to the landmarks it leads to, on average over
  // the upright faces of ../shared/data (75 faces; each face's own differs by
  // about 0.1 spread in place and 0.3 in size): the box a re-prediction takes.
  const BoxCalibration detector_box{{0.0, -0.12}, 2.9};
  Landmarks68 landmarks = landmark_detector_->Detect(gray, box, roll);
  for (int pass = 0; pass < 2; ++pass) {
    const double shown = PredictionRoll(LandmarkRoll(landmarks));
    if (std::abs(AngleDifference(shown, roll)) <= kRollTolerance) break;
    roll = shown;
    box = BoxFromLandmarks(landmarks, detector_box, roll);
    landmarks = landmark_detector_->Detect(gray, box, roll);
  }
  return landmarks;
}

void FaceTracker::AddTurnedDetections(const cv::Mat& gray, double scale, std::vector<Detection>& detections) {
  // A face between two searches' rolls may be found by both, and a face
  // tilted 30-45 degrees by the upright search too: MergeDetection keeps the
  // better-scoring detection, which tells the tilt better.
  auto search = [&](std::span<const double> rolls) {
    for (const std::vector<Detection>& found : detector_.DetectTurned(gray, rolls, scale)) {
      for (const Detection& d : found) MergeDetection(detections, d);
    }
  };
  search(kTiltedRolls);
  if (detections.empty()) search(kUpsideDownRolls);
  std::sort(detections.begin(), detections.end(), [](const Detection& a, const Detection& b) { return a.score > b.score; });
}

std::vector<Face> FaceTracker::DetectFaces(const cv::Mat& bgr, const Camera& camera) {
  const cv::Mat gray = ToGray(bgr, gray_);
  const double scale = StillDetectionScale(gray.cols, gray.rows);
  // HOG scores some real faces (glasses, a frown, hair over the brows: d8.jpg
  // at -0.3 to -0.5) below its usual threshold of 0. A photo with nothing
  // above 0 takes its single best window above kFallbackThreshold; the cat in
  // s39.jpg scores nothing above -0.8. One search gives both: windows scoring
  // below 0 come after the others and cannot suppress them.
  const std::vector<Detection> windows = detector_.Detect(gray, scale, kFallbackThreshold);
  std::vector<Detection> detections;
  std::copy_if(windows.begin(), windows.end(), std::back_inserter(detections),
               [](const Detection& d) { return d.score >= 0; });
  // A still is searched turned too (about half a second of CPU on a 2,000 px
  // photo): HOG finds some faces tilted 30-45 degrees upright, but the turned
  // search that finds the same face scores it better and tells its tilt.
  AddTurnedDetections(gray, scale, detections);
  if (detections.empty() && !windows.empty()) detections = {windows.front()};
  if (options_.largest_only && detections.size() > 1) {
    const auto largest = std::max_element(detections.begin(), detections.end(), [](const Detection& a, const Detection& b) {
      return a.box.area() < b.box.area();
    });
    detections = {*largest};
  }
  std::sort(detections.begin(), detections.end(), [](const Detection& a, const Detection& b) { return a.box.x < b.box.x; });
  std::vector<Face> faces;
  for (std::size_t i = 0; i < detections.size(); ++i) {
    Face face;
    face.id = static_cast<int>(i);
    face.box = detections[i].box;
    face.box_roll = detections[i].roll;
    face.confidence = ConfidenceFromScore(detections[i].score);
    face.landmarks = FindLandmarks(gray, face.box, face.box_roll);
    face.pose = EstimateHeadPose(face.landmarks, mean_face_, camera, nullptr, options_.head_pose);
    faces.push_back(face);
  }
  return faces;
}

FaceTracker::Track FaceTracker::StartTrack(const Detection& detection) {
  Track track;
  track.id = next_id_++;
  track.box = detection.box;
  track.roll = detection.roll;
  track.raw = FindLandmarks(gray_, track.box, track.roll);
  track.calibration = Calibrate(track.box, track.roll, track.raw);
  track.confidence = ConfidenceFromScore(detection.score);
  track.filters.assign(2 * kNumLandmarks,
                       OneEuroFilter(options_.smoothing_min_cutoff_hz, options_.smoothing_beta));
  return track;
}

std::vector<Detection> FaceTracker::SearchFrame() {
  const bool search = tracks_.empty() || ++frames_since_search_ >= options_.search_interval;
  std::vector<Detection> detections;
  if (search) {
    frames_since_search_ = 0;
    const double scale = VideoDetectionScale(gray_.cols, gray_.rows);
    detections = detector_.Detect(gray_, scale);
    // With no face in sight, tilted faces are searched for too, but only as
    // often as new faces are: that search costs four to seven upright ones.
    if (detections.empty() && tracks_.empty() &&
        (frames_since_turned_search_ < 0 || frames_since_turned_search_ >= options_.search_interval)) {
      frames_since_turned_search_ = 0;
      AddTurnedDetections(gray_, scale, detections);
    }
  }
  if (frames_since_turned_search_ >= 0) ++frames_since_turned_search_;
  return detections;
}

void FaceTracker::FollowTrack(Track& track, const std::vector<Detection>& detections, std::vector<bool>& used) {
  const double roll = PredictionRoll(LandmarkRoll(track.raw));
  const cv::Rect2d predicted = BoxFromLandmarks(track.raw, track.calibration, roll);
  int best = -1;
  double best_iou = 0.3;
  for (std::size_t d = 0; d < detections.size(); ++d) {
    const double iou = IntersectionOverUnion(predicted, detections[d].box);
    if (!used[d] && iou > best_iou) best = static_cast<int>(d), best_iou = iou;
  }
  track.roll = roll;
  if (best >= 0) {
    // A fresh detection re-anchors the box and its relation to the landmarks.
    used[best] = true;
    track.box = detections[best].box;
    track.raw = FindLandmarks(gray_, track.box, track.roll);
    track.calibration = Calibrate(track.box, track.roll, track.raw);
    track.confidence = ConfidenceFromScore(detections[best].score);
  } else {
    track.box = predicted;
    track.raw = FindLandmarks(gray_, track.box, track.roll);
    track.confidence = ConfidenceFromScore(detector_.Verify(gray_, track.box, -1.0, track.roll).score);
  }
  track.missed_frames = track.confidence < options_.missed_confidence ? track.missed_frames + 1 : 0;
}

void FaceTracker::StartNewTracks(const std::vector<Detection>& detections, const std::vector<bool>& used) {
  for (std::size_t d = 0; d < detections.size(); ++d) {
    if (used[d]) continue;
    const bool overlaps = std::any_of(tracks_.begin(), tracks_.end(),
                                      [&](const Track& track) { return SameFace(track.box, detections[d].box); });
    if (!overlaps) tracks_.push_back(StartTrack(detections[d]));
  }
}

void FaceTracker::DropDuplicateTracks() {
  // Two tracks that converged on one face: keep the older.
  for (std::size_t a = 0; a < tracks_.size(); ++a) {
    for (std::size_t b = a + 1; b < tracks_.size();) {
      if (IntersectionOverUnion(tracks_[a].box, tracks_[b].box) > 0.5) {
        tracks_.erase(tracks_.begin() + static_cast<std::ptrdiff_t>(b));
      } else {
        ++b;
      }
    }
  }
  if (options_.largest_only && tracks_.size() > 1) {
    const auto largest = std::max_element(tracks_.begin(), tracks_.end(), [](const Track& a, const Track& b) {
      return a.box.area() < b.box.area();
    });
    Track keep = std::move(*largest);
    tracks_.clear();
    tracks_.push_back(std::move(keep));
  }
}

std::vector<Face> FaceTracker::TrackFrame(const cv::Mat& bgr, double timestamp_s, const Camera& camera) {
  ToGray(bgr, gray_);
  if (bgr.channels() == 1) gray_ = bgr;
  const std::vector<Detection> detections = SearchFrame();
  std::vector<bool> used(detections.size(), false);
  for (Track& track : tracks_) FollowTrack(track, detections, used);
  std::erase_if(tracks_, [&](const Track& track) { return track.missed_frames >= options_.max_missed_frames; });
  StartNewTracks(detections, used);
  DropDuplicateTracks();

  std::vector<Face> faces;
  for (Track& track : tracks_) {
    Smooth(track, timestamp_s);
    faces.push_back(ToFace(track, camera, true));
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.id < b.id; });
  return faces;
}

void FaceTracker::Smooth(Track& track, double timestamp_s) {
  if (!options_.smooth) {
    track.smoothed = track.raw;
    return;
  }
  // The cutoff rises with speed measured in interocular distances per second,
  // which means the same for near and far faces.
  const double unit = std::max((track.raw[45] - track.raw[36]).norm(), 1.0);
  const double dt = timestamp_s - track.last_timestamp;
  for (int i = 0; i < kNumLandmarks; ++i) {
    track.smoothed[i].x() = track.filters[2 * i].Filter(track.raw[i].x(), dt, unit);
    track.smoothed[i].y() = track.filters[2 * i + 1].Filter(track.raw[i].y(), dt, unit);
  }
  track.last_timestamp = timestamp_s;
}

Face FaceTracker::ToFace(Track& track, const Camera& camera, bool use_previous_pose) {
  track.pose = EstimateHeadPose(track.smoothed, mean_face_, camera, use_previous_pose && track.has_pose ? &track.pose : nullptr,
                                options_.head_pose);
  track.has_pose = true;
  Face face;
  face.id = track.id;
  face.box = track.box;
  face.box_roll = track.roll;
  face.confidence = track.confidence;
  face.landmarks = track.smoothed;
  face.pose = track.pose;
  return face;
}

}  // namespace gazedirector
