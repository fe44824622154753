#include "gazedirector/eval/performance.h"

#include <atomic>
#include <thread>
#include <vector>

#include "gazedirector/io/video_reader.h"
#include "gazedirector/render/renderer.h"
#include "gazedirector/util/timer.h"

namespace gazedirector {

double MeasureLandmarksFps(const std::filesystem::path& video, FaceTracker& tracker) {
  VideoReader reader(video);
  const Camera camera = Camera::Default(reader.info().width, reader.info().height);
  tracker.Reset();
  cv::Mat frame;
  Timer timer;
  long frames = 0;
  while (reader.Read(frame)) {
    tracker.TrackFrame(frame, reader.timestamp_s(), camera);
    ++frames;
  }
  return frames / timer.Seconds();
}

double MeasureRendersPerSecond(std::shared_ptr<const EyeRegionModel> model, int threads, double seconds) {
  // The mean model at the distance where its two eye regions (about 130 mm
  // across) fill the 200 px width.
  const Camera camera{600, 600, 99.5, 49.5, 200, 100};
  Parameters phi;
  phi.block<Block::kTranslation>() = Eigen::Vector3d(0, 0, camera.fx * 130.0 / camera.width);
  std::atomic<long> renders{0};
  std::atomic<bool> stop{false};
  auto work = [&] {
    Renderer renderer(model);
    RenderBuffers buffers;
    Parameters local = phi;
    renderer.Render(local, camera, buffers);  // warm up: textures and buffers
    long count = 0;
    while (!stop.load(std::memory_order_relaxed)) {
      local.gaze_yaw() = (count % 2) ? 1.0 : -1.0;
      local.eyelid_pitch() = (count % 3) - 1.0;
      renderer.Render(local, camera, buffers);
      ++count;
    }
    renders += count;
  };
  std::vector<std::thread> workers;
  Timer timer;
  for (int i = 0; i < threads; ++i) workers.emplace_back(work);
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  stop = true;
  for (std::thread& worker : workers) worker.join();
  return renders / timer.Seconds();
}

}  // namespace gazedirector
