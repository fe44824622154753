#pragma once

#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "gazedirector/face/face.h"
#include "gazedirector/face/face_detector.h"
#include "gazedirector/face/head_pose.h"
#include "gazedirector/face/landmark_detector.h"
#include "gazedirector/face/mean_face.h"
#include "gazedirector/geometry/camera.h"
#include "gazedirector/util/one_euro_filter.h"

namespace gazedirector {

struct FaceTrackerOptions {
  bool largest_only = false;     // report only the largest face
  int search_interval = 15;      // video frames between full-frame searches for new faces
  int max_missed_frames = 4;     // a track the detector misses this many frames running is dropped
  double missed_confidence = 0.2;
  bool smooth = true;            // 1-euro smoothing of video landmarks
  double smoothing_min_cutoff_hz = 1.2;
  double smoothing_beta = 6.0;   // cutoff rise per interocular distance per second
  HeadPoseMethod head_pose = HeadPoseMethod::kPerspectiveNPoint;
};

// Finds faces, their 68 landmarks and head poses in stills and video frames.
// In video it detects once, then follows each face from frame to frame with
// the landmark predictor (a cheap detector check confirms the face is still
// there), searches the whole frame for new faces now and then, and keeps
// face ids stable for as long as a face stays tracked.
class FaceTracker {
 public:
  FaceTracker(std::shared_ptr<const LandmarkDetector> landmark_detector, MeanFace mean_face,
              FaceTrackerOptions options = {});

  // Every face in a still image, ids 0.. from left to right.
  std::vector<Face> DetectFaces(const cv::Mat& bgr, const Camera& camera);

  // The faces of the next video frame; ids persist across frames.
  std::vector<Face> TrackFrame(const cv::Mat& bgr, double timestamp_s, const Camera& camera);

  // Forgets all tracks (a cut in the video, or a new one).
  void Reset();

  const FaceTrackerOptions& options() const { return options_; }

 private:
  // Where the detector's box sits relative to the landmarks it produced:
  // box centre = centroid + spread * offset, box side = spread * size.
  // The offset is in the face's own frame (turned by the box's roll).
  struct BoxCalibration {
    Eigen::Vector2d offset = Eigen::Vector2d::Zero();
    double size = 0;
  };
  struct Track {
    int id = 0;
    cv::Rect2d box;
    double roll = 0;  // the box is turned by this about its centre (turned_crop.h)
    Landmarks68 raw{};
    BoxCalibration calibration;
    double confidence = 0;
    int missed_frames = 0;
    double last_timestamp = 0;
    std::vector<OneEuroFilter> filters;  // x and y of each landmark, in face units
    Landmarks68 smoothed{};
    HeadPose pose;
    bool has_pose = false;
  };

  static BoxCalibration Calibrate(const cv::Rect2d& box, double roll, const Landmarks68& landmarks);
  static cv::Rect2d BoxFromLandmarks(const Landmarks68& landmarks, const BoxCalibration& calibration, double roll);
  // The landmarks in `box` turned by `roll`, predicted once more upright to
  // the face when they show it tilted otherwise; `roll` becomes the one used.
  Landmarks68 FindLandmarks(const cv::Mat& gray, cv::Rect2d& box, double& roll) const;
  // Adds the faces standing upright in the image turned 45 and 90 degrees
  // either way to `detections`, and where there are none at all, those of the
  // image turned upside down (135 and 180 degrees); best first.
  void AddTurnedDetections(const cv::Mat& gray, double scale, std::vector<Detection>& detections);
  // A video frame's detections: upright ones every search_interval frames
  // (every frame while nothing is tracked), and turned ones while no face is
  // in sight.
  std::vector<Detection> SearchFrame();
  // Moves `track` to this frame: re-anchored on the best unused detection
  // overlapping its predicted box (marked used), else on the prediction.
  void FollowTrack(Track& track, const std::vector<Detection>& detections, std::vector<bool>& used);
  // A track for each unused detection that is not a tracked face.
  void StartNewTracks(const std::vector<Detection>& detections, const std::vector<bool>& used);
  // Of tracks that converged on one face, the older; with largest_only, the largest.
  void DropDuplicateTracks();
  Track StartTrack(const Detection& detection);
  void Smooth(Track& track, double timestamp_s);
  Face ToFace(Track& track, const Camera& camera, bool use_previous_pose);

  std::shared_ptr<const LandmarkDetector> landmark_detector_;
  MeanFace mean_face_;
  FaceTrackerOptions options_;
  FaceDetector detector_;
  cv::Mat gray_;
  std::vector<Track> tracks_;
  int next_id_ = 0;
  long frames_since_search_ = 0;
  long frames_since_turned_search_ = -1;  // -1: none yet
};

// The scale at which whole frames are searched: stills are upsampled up to 2x
// to find faces down to 40 px; video frames are searched at no more than
// 800 px across for speed.
double StillDetectionScale(int width, int height);
double VideoDetectionScale(int width, int height);

}  // namespace gazedirector
