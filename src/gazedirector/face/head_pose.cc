#include "gazedirector/face/head_pose.h"

#include <cmath>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace gazedirector {
namespace {

constexpr int kFirstRigid = 17;  // brows
constexpr int kLastRigid = 47;   // end of the eyes

}  // namespace

HeadPose EstimateHeadPose(const Landmarks68& landmarks, const MeanFace& mean_face, const Camera& camera,
                          const HeadPose* previous) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (int i = kFirstRigid; i <= kLastRigid; ++i) {
    object.emplace_back(mean_face[i].x(), mean_face[i].y(), mean_face[i].z());
    image.emplace_back(landmarks[i].x(), landmarks[i].y());
  }
  cv::Mat k;
  cv::eigen2cv(camera.K(), k);
  cv::Mat rvec, tvec;
  bool use_guess = false;
  if (previous != nullptr && previous->translation.z() > 0) {
    cv::Mat r;
    cv::eigen2cv(previous->rotation, r);
    cv::Rodrigues(r, rvec);
    tvec = (cv::Mat_<double>(3, 1) << previous->translation.x(), previous->translation.y(), previous->translation.z());
    use_guess = true;
  } else {
    // Frontal, at the distance that matches the landmarks' spread.
    const double spread_px = (landmarks[45] - landmarks[36]).norm();
    const double spread_mm = (mean_face[45] - mean_face[36]).norm();
    const double z = spread_px > 1 ? camera.fx * spread_mm / spread_px : 600.0;
    rvec = cv::Mat::zeros(3, 1, CV_64F);
    tvec = (cv::Mat_<double>(3, 1) << 0, 0, z);
    use_guess = true;
  }
  cv::solvePnP(object, image, k, cv::noArray(), rvec, tvec, use_guess, cv::SOLVEPNP_ITERATIVE);

  HeadPose pose;
  cv::Mat rotation;
  cv::Rodrigues(rvec, rotation);
  cv::cv2eigen(rotation, pose.rotation);
  pose.translation = Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  double squared = 0;
  for (std::size_t i = 0; i < object.size(); ++i) {
    const Eigen::Vector3d p = pose.rotation * Eigen::Vector3d(object[i].x, object[i].y, object[i].z) + pose.translation;
    squared += (camera.Project(p) - Eigen::Vector2d(image[i].x, image[i].y)).squaredNorm();
  }
  pose.reprojection_error_px = std::sqrt(squared / static_cast<double>(object.size()));
  return pose;
}

}  // namespace gazedirector
