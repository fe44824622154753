#include "gazedirector/render/model_bounds.h"

#include <gtest/gtest.h>

#include "gazedirector/render/renderer.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::SharedModel;

// The fitter crops the photo to these bounds, so every pixel the model
// renders must lie inside them (the eyeballs sit behind the skin's opening).
// The margin-free bounds are tight: they come from the control mesh, which
// the subdivided surface lies just within, and the render covers pixel
// centres only, so it reaches within a few pixels of each side.
TEST(ModelBoundsTest, TheRenderLiesWithinTheBoundsAndReachesTheirSides) {
  const Camera camera = Camera::Default(640, 480);
  for (double yaw : {-25.0, 0.0, 20.0}) {
    Parameters phi;
    phi.block<Block::kTranslation>() = Eigen::Vector3d(-20, 10, 450);
    phi.block<Block::kRotation>() = Eigen::Vector3d(5, yaw, 0);
    phi.gaze_yaw() = -0.5 * yaw;
    Renderer renderer(SharedModel());
    RenderBuffers buffers;
    renderer.Render(phi, camera, buffers);
    ASSERT_FALSE(buffers.foreground.empty());
    int x0 = camera.width, y0 = camera.height, x1 = -1, y1 = -1;
    for (int pixel : buffers.foreground) {
      const int x = pixel % camera.width, y = pixel / camera.width;
      x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
    }
    const cv::Rect tight = ModelBounds(renderer.posed(), camera, 0.0);
    EXPECT_TRUE(tight.contains({x0, y0}) && tight.contains({x1, y1})) << "yaw " << yaw << ": " << tight;
    EXPECT_LE(x0 - tight.x, 3) << "yaw " << yaw;
    EXPECT_LE(tight.br().x - 1 - x1, 3) << "yaw " << yaw;
    EXPECT_LE(y0 - tight.y, 3) << "yaw " << yaw;
    EXPECT_LE(tight.br().y - 1 - y1, 3) << "yaw " << yaw;
    const cv::Rect grown = ModelBounds(renderer.posed(), camera);
    EXPECT_EQ(grown & tight, tight);
    EXPECT_GT(grown.width, tight.width);
  }
}

// The redirection counts eyeball pixels within these bounds only: every
// pixel a render gives an eyeball lies inside them, over gazes, lids and
// head turns, and they are far smaller than the eye regions' bounds.
TEST(ModelBoundsTest, TheEyeballsRenderWithinTheirBounds) {
  const Camera camera = Camera::Default(640, 480);
  Renderer renderer(SharedModel());
  RenderBuffers buffers;
  for (double yaw : {-25.0, 0.0, 20.0}) {
    for (double gaze_pitch : {-30.0, 0.0, 25.0}) {
      Parameters phi;
      phi.block<Block::kTranslation>() = Eigen::Vector3d(-20, 10, 450);
      phi.block<Block::kRotation>() = Eigen::Vector3d(5, yaw, 0);
      phi.gaze_pitch() = gaze_pitch;
      phi.gaze_yaw() = -0.5 * yaw;
      phi.eyelid_pitch() = gaze_pitch;
      renderer.Render(phi, camera, buffers);
      const cv::Rect eyeballs = EyeballBounds(renderer.posed(), camera);
      int inside = 0;
      for (int pixel : buffers.foreground) {
        if (!IsEyeball(buffers.PartAt(pixel))) continue;
        ASSERT_TRUE(eyeballs.contains({pixel % camera.width, pixel / camera.width})) << "yaw " << yaw;
        ++inside;
      }
      EXPECT_GT(inside, 100) << "yaw " << yaw << " pitch " << gaze_pitch;
      EXPECT_LT(eyeballs.area(), 0.6 * ModelBounds(renderer.posed(), camera, 0.0).area()) << "yaw " << yaw;
    }
  }
}

TEST(ModelBoundsTest, AModelOutsideTheImageOrBehindTheCameraHasNoBounds) {
  const Camera camera = Camera::Default(640, 480);
  PosedModel posed;
  PoseWorkspace workspace;
  Parameters phi;
  phi.block<Block::kTranslation>() = Eigen::Vector3d(2000, 0, 450);
  SharedModel()->Pose(phi, posed, workspace);
  EXPECT_TRUE(ModelBounds(posed, camera).empty());
  phi.block<Block::kTranslation>() = Eigen::Vector3d(0, 0, -300);
  SharedModel()->Pose(phi, posed, workspace);
  EXPECT_TRUE(ModelBounds(posed, camera).empty());
  EXPECT_TRUE(EyeballBounds(posed, camera).empty());
}

}  // namespace
}  // namespace gazedirector
