#include "gazedirector/redirect/glints.h"

#include <cstdio>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "gazedirector/fit/face_fit.h"
#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/model/eye_region_topology.h"
#include "gazedirector/redirect/gaze_target.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::SharedModel;

// The centre of the sphere through the central corneal bulge of `eye` (the
// posed eyeball's vertices over 12.5 mm from its centre) for `phi`, camera
// frame: least squares on |p|^2 = 2 p.c + (r^2 - |c|^2).
Eigen::Vector3d CorneaSphereCentre(const Parameters& phi, int eye) {
  PosedModel posed;
  PoseWorkspace work;
  SharedModel()->Pose(phi, posed, work);
  const Eigen::Matrix3Xf& p = posed.parts[EyeballPart(eye)].positions;
  const Eigen::Vector3d centre = EyeGazes(phi)[eye].centre;
  std::vector<Eigen::Vector3d> bulge;
  for (Eigen::Index v = 0; v < p.cols(); ++v) {
    const Eigen::Vector3d point = p.col(v).cast<double>();
    if ((point - centre).norm() > 12.5) bulge.push_back(point);
  }
  Eigen::MatrixXd a(bulge.size(), 4);
  Eigen::VectorXd b(bulge.size());
  for (std::size_t i = 0; i < bulge.size(); ++i) {
    a.row(static_cast<Eigen::Index>(i)) << 2 * bulge[i].transpose(), 1;
    b(static_cast<Eigen::Index>(i)) = bulge[i].squaredNorm();
  }
  return a.colPivHouseholderQr().solve(b).head<3>();
}

// A glint moves as the centre of the cornea's curvature: the posed mesh's
// corneal sphere, fitted afresh here, moves in the image as GlintShifts says,
// about 0.58 of the iris centre's motion (6.22 against 10.75 mm forward).
TEST(GlintsTest, GlintsMoveAsTheMeshsCorneaCentreMoves) {
  Parameters fitted;
  fitted.block<Block::kTranslation>() = Eigen::Vector3d(20, -10, 450);
  fitted.gaze_pitch() = 5, fitted.gaze_yaw() = -10;
  Camera camera;
  camera.fx = camera.fy = 1200, camera.cx = 640, camera.cy = 360, camera.width = 1280, camera.height = 720;
  for (const auto& [pitch, yaw] : {std::pair(0.0, 25.0), std::pair(-15.0, 0.0), std::pair(10.0, -10.0)}) {
    const Parameters target = Retarget(fitted, GazeTarget::Offset(pitch, yaw));
    const std::array<cv::Vec2f, 2> shifts = GlintShifts(fitted, target, camera);
    for (int eye = 0; eye < 2; ++eye) {
      const Eigen::Vector2d mesh = camera.Project(CorneaSphereCentre(target, eye)) -
                                   camera.Project(CorneaSphereCentre(fitted, eye));
      const EyeGaze from = EyeGazes(fitted)[eye], to = EyeGazes(target)[eye];
      const Eigen::Vector2d iris = camera.Project(to.centre + topology::kLimbusDepthMm * to.gaze) -
                                   camera.Project(from.centre + topology::kLimbusDepthMm * from.gaze);
      const Eigen::Vector2d glint(shifts[eye][0], shifts[eye][1]);
      std::printf("pitch %+.0f yaw %+.0f eye %d: glint (%.2f, %.2f) px, mesh's cornea (%.2f, %.2f), iris (%.2f, %.2f)\n",
                  pitch, yaw, eye, glint.x(), glint.y(), mesh.x(), mesh.y(), iris.x(), iris.y());
      EXPECT_LT((glint - mesh).norm(), 0.05 * mesh.norm() + 0.1);
      EXPECT_NEAR(glint.norm() / iris.norm(), topology::kCorneaCentreMm / topology::kLimbusDepthMm, 0.05);
    }
  }
}

}  // namespace
}  // namespace gazedirector
