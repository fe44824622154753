#include "gazedirector/face/head_pose.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "gazedirector/geometry/kabsch.h"

namespace gazedirector {
namespace {

constexpr int kFirstRigid = 17;  // brows
constexpr int kLastRigid = 47;   // end of the eyes
constexpr int kKabschIterations = 1000;
constexpr double kKabschToleranceMm = 1e-4;
constexpr double kFaceRadiusMm = 80;  // turns the rotation's change into millimetres moved

// Refines the pose by OpenCV's iterative perspective-n-point from its start.
void SolvePerspectiveNPoint(const std::vector<Eigen::Vector3d>& object, const std::vector<Eigen::Vector2d>& image,
                            const Camera& camera, Eigen::Matrix3d& rotation, Eigen::Vector3d& translation) {
  std::vector<cv::Point3d> object_points;
  std::vector<cv::Point2d> image_points;
  for (std::size_t i = 0; i < object.size(); ++i) {
    object_points.emplace_back(object[i].x(), object[i].y(), object[i].z());
    image_points.emplace_back(image[i].x(), image[i].y());
  }
  cv::Mat k, r, rvec;
  cv::eigen2cv(camera.K(), k);
  cv::eigen2cv(rotation, r);
  cv::Rodrigues(r, rvec);
  cv::Mat tvec = (cv::Mat_<double>(3, 1) << translation.x(), translation.y(), translation.z());
  cv::solvePnP(object_points, image_points, k, cv::noArray(), rvec, tvec, /*useExtrinsicGuess=*/true,
               cv::SOLVEPNP_ITERATIVE);
  cv::Rodrigues(rvec, r);
  cv::cv2eigen(r, rotation);
  translation = Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
}

// Lu, Hager and Mjolsness's orthogonal iteration: lifts each landmark onto
// its line of sight where the posed face comes closest, turns the face onto
// the lifted points by Kabsch, and places it where it lies closest to the
// lines of sight for that turn (in closed form; Kabsch's own translation
// would creep in depth over hundreds of steps for a small face).
void AlignByKabsch(const std::vector<Eigen::Vector3d>& object, const std::vector<Eigen::Vector2d>& image,
                   const Camera& camera, Eigen::Matrix3d& rotation, Eigen::Vector3d& translation) {
  const int n = static_cast<int>(object.size());
  const Eigen::Matrix3d to_ray = camera.K().inverse();
  Eigen::Matrix3Xd face(3, n);
  std::vector<Eigen::Matrix3d> onto_sight(n);  // projections onto each line of sight
  Eigen::Matrix3d mean_onto = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) {
    face.col(i) = object[i];
    const Eigen::Vector3d ray = (to_ray * image[i].homogeneous()).normalized();
    onto_sight[i] = ray * ray.transpose();
    mean_onto += onto_sight[i] / n;
  }
  const Eigen::Matrix3d place = (Eigen::Matrix3d::Identity() - mean_onto).inverse();
  auto closest_translation = [&](const Eigen::Matrix3d& turn) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int i = 0; i < n; ++i) sum += (onto_sight[i] - Eigen::Matrix3d::Identity()) * (turn * face.col(i));
    return Eigen::Vector3d(place * sum / n);
  };
  for (int iteration = 0; iteration < kKabschIterations; ++iteration) {
    Eigen::Matrix3Xd lifted(3, n);
    for (int i = 0; i < n; ++i) lifted.col(i) = onto_sight[i] * (rotation * face.col(i) + translation);
    const Eigen::Matrix3d turn = KabschAlign(face, lifted).rotation;
    const Eigen::Vector3d shift = closest_translation(turn);
    const double moved =
        (shift - translation).norm() + Eigen::AngleAxisd(turn * rotation.transpose()).angle() * kFaceRadiusMm;
    rotation = turn;
    translation = shift;
    if (moved < kKabschToleranceMm) break;
  }
}

}  // namespace

HeadPose EstimateHeadPose(const Landmarks68& landmarks, const MeanFace& mean_face, const Camera& camera,
                          const HeadPose* previous, HeadPoseMethod method) {
  std::vector<Eigen::Vector3d> object;
  std::vector<Eigen::Vector2d> image;
  for (int i = kFirstRigid; i <= kLastRigid; ++i) {
    object.push_back(mean_face[i]);
    image.push_back(landmarks[i]);
  }
  HeadPose pose;
  if (previous != nullptr && previous->translation.z() > 0) {
    pose.rotation = previous->rotation;
    pose.translation = previous->translation;
  } else {
    // Frontal, at the distance that matches the landmarks' spread.
    const double spread_px = (landmarks[45] - landmarks[36]).norm();
    const double spread_mm = (mean_face[45] - mean_face[36]).norm();
    pose.rotation.setIdentity();
    pose.translation = Eigen::Vector3d(0, 0, spread_px > 1 ? camera.fx * spread_mm / spread_px : 600.0);
  }
  if (method == HeadPoseMethod::kKabsch) {
    AlignByKabsch(object, image, camera, pose.rotation, pose.translation);
  } else {
    SolvePerspectiveNPoint(object, image, camera, pose.rotation, pose.translation);
  }
  double squared = 0;
  for (std::size_t i = 0; i < object.size(); ++i) {
    squared += (camera.Project(pose.rotation * object[i] + pose.translation) - image[i]).squaredNorm();
  }
  pose.reprojection_error_px = std::sqrt(squared / static_cast<double>(object.size()));
  return pose;
}

}  // namespace gazedirector
