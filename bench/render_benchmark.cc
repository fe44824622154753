// Micro-benchmarks of the renderer's stages on the real eye-region model.
#include <benchmark/benchmark.h>

#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/render/renderer.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

// Both eye regions filling a 200x100 region of interest, as when fitting.
struct Scene {
  std::shared_ptr<const EyeRegionModel> model = EyeRegionModel::Load(testing::TestAssets());
  Camera camera{600, 600, 99.5, 49.5, 200, 100};
  Parameters phi;
  Scene() { phi.block<Block::kTranslation>() = Eigen::Vector3d(0, 0, 600.0 * 130 / 200); }
};

Scene& TheScene() {
  static Scene scene;
  return scene;
}

void BM_Pose(benchmark::State& state) {
  Scene& scene = TheScene();
  Renderer renderer(scene.model);
  for (auto _ : state) renderer.Pose(scene.phi);
}
BENCHMARK(BM_Pose);

void BM_Rasterize(benchmark::State& state) {
  Scene& scene = TheScene();
  Renderer renderer(scene.model);
  RenderBuffers buffers;
  renderer.Pose(scene.phi);
  for (auto _ : state) renderer.Rasterize(scene.camera, buffers);
  state.counters["pixels"] = static_cast<double>(buffers.foreground.size());
}
BENCHMARK(BM_Rasterize);

void BM_Shade(benchmark::State& state) {
  Scene& scene = TheScene();
  Renderer renderer(scene.model);
  RenderBuffers buffers;
  renderer.Render(scene.phi, scene.camera, buffers);
  for (auto _ : state) renderer.Shade(scene.phi, scene.camera, buffers);
}
BENCHMARK(BM_Shade);

// Looking down, the skin's look-down texture is mixed in.
void BM_ShadeLookingDown(benchmark::State& state) {
  Scene& scene = TheScene();
  Renderer renderer(scene.model);
  RenderBuffers buffers;
  Parameters phi = scene.phi;
  phi.eyelid_pitch() = -12;
  renderer.Render(phi, scene.camera, buffers);
  for (auto _ : state) renderer.Shade(phi, scene.camera, buffers);
}
BENCHMARK(BM_ShadeLookingDown);

void BM_Render(benchmark::State& state) {
  Scene& scene = TheScene();
  Renderer renderer(scene.model);
  RenderBuffers buffers;
  Parameters phi = scene.phi;
  int i = 0;
  for (auto _ : state) {
    phi.gaze_yaw() = (i++ % 2) ? 0.5 : -0.5;
    renderer.Render(phi, scene.camera, buffers);
  }
}
BENCHMARK(BM_Render);

// A new texture coefficient τ (each fresh fit's line search tries several):
// both skin textures composed and their mips built.
void BM_ComposeSkinTexture(benchmark::State& state) {
  const SkinTextureModel& skin = TheScene().model->skin_texture();
  RgbaTexture ahead, down;
  std::vector<double> tau(skin.num_modes(), 0.3);  // a fitted τ moves every mode
  int i = 0;
  for (auto _ : state) {
    tau[0] = (i++ % 2) ? 0.5 : -0.5;
    skin.Compose(tau.data(), ahead, down);
  }
}
BENCHMARK(BM_ComposeSkinTexture);

}  // namespace
}  // namespace gazedirector
