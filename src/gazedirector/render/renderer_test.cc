#include "gazedirector/render/renderer.h"

#include <array>
#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "tests/test_data.h"

// Counts heap allocations while a test asks for it (replaces the global
// operator new for this test binary; counting is off by default). The
// replacements pair malloc with free, which GCC cannot see through.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace
void* operator new(std::size_t size) {
  if (g_counting.load(std::memory_order_relaxed)) ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void* operator new(std::size_t size, std::align_val_t alignment) {
  if (g_counting.load(std::memory_order_relaxed)) ++g_allocations;
  const std::size_t a = static_cast<std::size_t>(alignment);
  if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size, std::align_val_t alignment) { return operator new(size, alignment); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace gazedirector {
namespace {

using testing::SharedModel;

// Both eye regions filling a 200x100 region, as when fitting.
const Camera kCamera{600, 600, 99.5, 49.5, 200, 100};
Parameters Framed() {
  Parameters phi;
  phi.block<Block::kTranslation>() = Eigen::Vector3d(0, 0, 390);
  return phi;
}

TEST(RendererTest, RendersAreDeterministicBitForBit) {
  Renderer first(SharedModel()), second(SharedModel());
  RenderBuffers a, b, c;
  Parameters phi = Framed();
  phi.gaze_yaw() = 7.3;
  phi.eyelid_pitch() = -12;  // the look-down skin mixed in
  first.Render(phi, kCamera, a);
  second.Render(phi, kCamera, b);
  Parameters other = phi;
  other.gaze_yaw() = -4;
  other.eyelid_pitch() = -20;
  other.texture()[1] = 0.5;
  first.Render(other, kCamera, c);  // something else in between, with another skin and mix
  first.Render(phi, kCamera, c);
  ASSERT_EQ(a.foreground, b.foreground);
  ASSERT_EQ(a.foreground, c.foreground);
  EXPECT_TRUE((a.colour.array() == b.colour.array()).all());
  EXPECT_TRUE((a.colour.array() == c.colour.array()).all());
}

// Culling the eyeball's patches skips only triangles that would not have
// shown: the buffers match drawing them all, over gazes, head turns, lids and
// distances (near enough for perspective to matter).
TEST(RendererTest, CullingEyeballPatchesChangesNoPixel) {
  Renderer culling(SharedModel()), drawing_all(SharedModel());
  drawing_all.set_eyeball_culling(false);
  RenderBuffers culled, all;
  int renders = 0;
  for (double distance : {390.0, 150.0}) {
    for (double head_yaw : {-30.0, 0.0, 25.0}) {
      for (double gaze_pitch : {-35.0, 0.0, 25.0}) {
        for (double gaze_yaw : {-45.0, -10.0, 30.0}) {
          Parameters phi = Framed();
          phi.block<Block::kTranslation>() = Eigen::Vector3d(head_yaw / 3, 5, distance);
          phi.block<Block::kRotation>() = Eigen::Vector3d(10, head_yaw, 0);
          phi.gaze_pitch() = gaze_pitch;
          phi.gaze_yaw() = gaze_yaw;
          phi.eyelid_pitch() = gaze_pitch / 2;
          culling.Render(phi, kCamera, culled);
          drawing_all.Render(phi, kCamera, all);
          ASSERT_EQ(culled.foreground, all.foreground) << "render " << renders;
          for (int pixel : all.foreground) {
            ASSERT_EQ(culled.visibility.triangle(pixel), all.visibility.triangle(pixel)) << "render " << renders;
            ASSERT_EQ(culled.visibility.depth(pixel), all.visibility.depth(pixel));
          }
          ++renders;
        }
      }
    }
  }
  EXPECT_EQ(renders, 54);
}

// A camera cropped to a window rasterizes the window's pixels as the whole
// view does (the redirection counts eyeball pixels in the eyeballs' own
// bounds only), over gazes, lids and head turns.
TEST(RendererTest, ACroppedCameraRasterizesTheWindowAsTheWholeViewDoes) {
  Renderer renderer(SharedModel());
  RenderBuffers whole, window;
  int windows = 0;
  for (double head_yaw : {-25.0, 0.0, 20.0}) {
    for (double gaze_pitch : {-30.0, 0.0, 20.0}) {
      Parameters phi = Framed();
      phi.block<Block::kRotation>() = Eigen::Vector3d(5, head_yaw, 0);
      phi.gaze_pitch() = gaze_pitch;
      phi.gaze_yaw() = head_yaw / 2;
      phi.eyelid_pitch() = gaze_pitch;
      renderer.Pose(phi);
      renderer.Rasterize(kCamera, whole);
      const cv::Mat parts = whole.PartImage();
      for (const cv::Rect& crop : {cv::Rect(37, 21, 90, 50), cv::Rect(0, 0, 200, 100), cv::Rect(120, 30, 80, 70),
                                   cv::Rect(3, 40, 61, 33)}) {
        renderer.Rasterize(kCamera.Cropped(crop.x, crop.y, crop.width, crop.height), window);
        ASSERT_EQ(cv::norm(window.PartImage(), parts(crop), cv::NORM_INF), 0.0)
            << "head " << head_yaw << " pitch " << gaze_pitch << " window " << crop;
        ++windows;
      }
    }
  }
  EXPECT_EQ(windows, 36);
}

TEST(RendererTest, MaskAndPartIdsAgreeAndShowFourParts) {
  Renderer renderer(SharedModel());
  RenderBuffers buffers;
  renderer.Render(Framed(), kCamera, buffers);
  const cv::Mat mask = buffers.MaskImage(), parts = buffers.PartImage();
  int counts[4] = {0, 0, 0, 0};
  for (int i = 0; i < mask.rows * mask.cols; ++i) {
    EXPECT_EQ(mask.data[i] == 255, parts.data[i] != 255) << "pixel " << i;
    if (parts.data[i] < 4) ++counts[parts.data[i]];
  }
  // The skin fills most of the region; each eyeball shows through its opening.
  EXPECT_GT(counts[kLeftSkin], 4000);
  EXPECT_GT(counts[kRightSkin], 4000);
  EXPECT_GT(counts[kLeftEyeball], 300);
  EXPECT_GT(counts[kRightEyeball], 300);
  // The subject's left eye is on the image right.
  double left_x = 0, right_x = 0;
  for (int i = 0; i < mask.rows * mask.cols; ++i) {
    if (parts.data[i] == kLeftEyeball) left_x += i % mask.cols;
    if (parts.data[i] == kRightEyeball) right_x += i % mask.cols;
  }
  EXPECT_GT(left_x / counts[kLeftEyeball], 100);
  EXPECT_LT(right_x / counts[kRightEyeball], 100);
  // Colours are in range, the iris darker than the skin.
  EXPECT_GE(buffers.colour.minCoeff(), 0.0f);
  EXPECT_LE(buffers.colour.maxCoeff(), 1.5f);
}

TEST(RendererTest, AttributesInterpolateLinearlyOnScreen) {
  Renderer renderer(SharedModel());
  RenderBuffers buffers;
  renderer.Render(Framed(), kCamera, buffers);
  // The screen position of each vertex, interpolated, must give back each
  // pixel's own position (affine interpolation; vertices snap to 1/16 px).
  std::array<Eigen::MatrixXf, kNumParts> screen;
  for (int part = 0; part < kNumParts; ++part) {
    const Eigen::Matrix3Xf& p = renderer.posed().parts[part].positions;
    screen[part].resize(2, p.cols());
    for (Eigen::Index i = 0; i < p.cols(); ++i) {
      screen[part](0, i) = static_cast<float>(kCamera.fx * p(0, i) / p(2, i) + kCamera.cx);
      screen[part](1, i) = static_cast<float>(kCamera.fy * p(1, i) / p(2, i) + kCamera.cy);
    }
  }
  const cv::Mat field = Renderer::InterpolateAttribute(buffers, *SharedModel(), screen, 2);
  for (int pixel : buffers.foreground) {
    const cv::Vec2f value = field.at<cv::Vec2f>(pixel / kCamera.width, pixel % kCamera.width);
    ASSERT_NEAR(value[0], pixel % kCamera.width, 0.04);
    ASSERT_NEAR(value[1], pixel / kCamera.width, 0.04);
  }
}

TEST(RendererTest, LightAndTintChangeColoursAsLambertianShadingPredicts) {
  Renderer renderer(SharedModel());
  RenderBuffers bright, dim;
  Parameters phi = Framed();
  renderer.Render(phi, kCamera, bright);
  phi.block<Block::kAmbient>() *= 0.5;
  phi.block<Block::kLightColour>() *= 0.5;
  renderer.Render(phi, kCamera, dim);
  ASSERT_EQ(bright.foreground, dim.foreground);
  EXPECT_LT((dim.colour * 2 - bright.colour).cwiseAbs().maxCoeff(), 1e-5) << "colour is linear in the light";
}

// Eyeball pixels of `phi` rendered close up (irises about 27 px across)
// darker than each of `levels` (luminance).
std::array<int, 2> DarkEyeballPixels(const Parameters& phi, std::array<float, 2> levels) {
  const Camera close_up{1800, 1800, 299.5, 149.5, 600, 300};
  Renderer renderer(SharedModel());
  RenderBuffers buffers;
  renderer.Render(phi, close_up, buffers);
  std::array<int, 2> counts = {0, 0};
  for (std::size_t i = 0; i < buffers.foreground.size(); ++i) {
    if (!IsEyeball(buffers.PartAt(buffers.foreground[i]))) continue;
    const Eigen::Index row = static_cast<Eigen::Index>(i);
    const float luminance = 0.299f * buffers.colour(row, 0) + 0.587f * buffers.colour(row, 1) + 0.114f * buffers.colour(row, 2);
    for (int k = 0; k < 2; ++k) counts[k] += luminance < levels[k];
  }
  return counts;
}

TEST(RendererTest, ThePupilSizeResizesThePupilAndKeepsTheIrissEdge) {
  Parameters phi = Framed();
  const auto [pupil, iris] = DarkEyeballPixels(phi, {0.03f, 0.2f});
  ASSERT_GT(pupil, 400) << "both pupils, about 13 px in radius";
  phi.pupil_size() = 0.25;
  const auto [small_pupil, same_iris] = DarkEyeballPixels(phi, {0.03f, 0.2f});
  // The area goes with the radius squared: (0.25 / 0.49)^2 = 0.26.
  const double ratio = static_cast<double>(small_pupil) / pupil;
  EXPECT_GT(ratio, 0.18);
  EXPECT_LT(ratio, 0.36);
  // The iris (darker than the sclera) keeps its extent: only its inside stretches.
  EXPECT_NEAR(same_iris, iris, 0.03 * iris);
}

// The exact derivatives of colour for the appearance and light parameters
// agree with central differences of two renders.
TEST(RendererTest, ExactJacobianMatchesNumericalDerivatives) {
  Renderer renderer(SharedModel());
  RenderBuffers buffers, plus, minus;
  Parameters phi = Framed();
  phi.eyelid_pitch() = -12;  // the look-down texture blends in
  phi.gaze_pitch() = -12;
  phi.texture()[2] = 0.7;
  phi.block<Block::kLightDirection>() = Eigen::Vector2d(25, -15);  // above and to the image's left
  renderer.Render(phi, kCamera, buffers);
  Eigen::MatrixXf analytic;
  renderer.ExactJacobian(phi, kCamera, buffers, analytic);
  const std::vector<int>& parameters = Renderer::ExactParameters();
  ASSERT_EQ(analytic.cols(), static_cast<Eigen::Index>(parameters.size()));
  ASSERT_EQ(parameters.size(), 22u);
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const double h = 0.05;
    Parameters up = phi, down = phi;
    up[parameters[k]] += h;
    down[parameters[k]] -= h;
    renderer.Render(up, kCamera, plus);
    renderer.Render(down, kCamera, minus);
    ASSERT_EQ(plus.foreground, buffers.foreground) << "coverage does not depend on appearance";
    const Eigen::MatrixXf numerical = (plus.colour - minus.colour) / static_cast<float>(2 * h);
    // Row 3i + c of the analytic matrix is channel c of pixel i.
    const Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> per_pixel(
        analytic.col(static_cast<Eigen::Index>(k)).data(), numerical.rows(), 3);
    const float scale = std::max(1e-3f, numerical.cwiseAbs().maxCoeff());
    EXPECT_LT((per_pixel - numerical).cwiseAbs().maxCoeff(), 2e-3f * scale) << Parameters::NameOf(parameters[k]);
    EXPECT_GT(numerical.cwiseAbs().maxCoeff(), 1e-3f) << Parameters::NameOf(parameters[k]) << " changes some pixel";
  }
}

// Asking for some of the exact columns gives those columns of the full
// matrix, in the order asked.
TEST(RendererTest, ExactJacobianOfSomeParametersMatchesTheFullOne) {
  Renderer renderer(SharedModel());
  RenderBuffers buffers;
  Parameters phi = Framed();
  phi.eyelid_pitch() = -12;
  renderer.Render(phi, kCamera, buffers);
  Eigen::MatrixXf full, some;
  renderer.ExactJacobian(phi, kCamera, buffers, full);
  // light (blue), texture modes 3 and 0, iris, sclera, ambient, the light's yaw
  const std::vector<int> which = {19, 3, 8, 12, 0, 15, 21};
  renderer.ExactJacobian(phi, kCamera, buffers, which, some);
  ASSERT_EQ(some.cols(), static_cast<Eigen::Index>(which.size()));
  for (std::size_t k = 0; k < which.size(); ++k) {
    EXPECT_EQ((some.col(static_cast<Eigen::Index>(k)) - full.col(which[k])).cwiseAbs().maxCoeff(), 0.0f) << which[k];
  }
}

TEST(RendererTest, SteadyStateRenderingAllocatesNothing) {
  Renderer renderer(SharedModel());
  RenderBuffers buffers;
  Parameters phi = Framed();
  renderer.Render(phi, kCamera, buffers);  // warm up: buffers reach their sizes
  phi.gaze_yaw() = 3;
  renderer.Render(phi, kCamera, buffers);
  g_allocations = 0;
  g_counting = true;
  {
    // The counter works: a vector allocates once.
    std::vector<int> probe(10);
    EXPECT_EQ(g_allocations.load(), 1);
  }
  g_allocations = 0;
  for (int i = 0; i < 20; ++i) {
    phi.gaze_yaw() = (i % 2) ? 2.0 : -2.0;
    phi.eyelid_pitch() = (i % 3) - 1.0;
    renderer.Render(phi, kCamera, buffers);
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
}

}  // namespace
}  // namespace gazedirector
