#include "gazedirector/eval/performance.h"

#include <atomic>
#include <thread>
#include <vector>

#include "gazedirector/io/video_reader.h"
#include "gazedirector/redirect/gaze_target.h"
#include "gazedirector/redirect/redirector.h"
#include "gazedirector/render/renderer.h"
#include "gazedirector/video/gaze_tracker.h"
#include "gazedirector/video/tracked_frame_reader.h"
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

TrackedClip LoadTrackedClip(const std::filesystem::path& video, FaceTracker& tracker, int max_frames) {
  VideoReader reader(video);
  TrackedClip clip;
  clip.camera = Camera::Default(reader.info().width, reader.info().height);
  tracker.Reset();
  cv::Mat frame;
  while (static_cast<int>(clip.frames.size()) < max_frames && reader.Read(frame)) {
    const std::vector<Face> faces = tracker.TrackFrame(frame, reader.timestamp_s(), clip.camera);
    if (faces.empty()) continue;
    clip.frames.push_back(frame.clone());
    clip.faces.push_back(faces.front());
  }
  return clip;
}

namespace {

// Fits every frame of `clip` as the video tracker does: the first fresh, the
// rest warm-started with the settled parameters held. `warm_seconds` gets
// the time of the warm fits.
std::vector<Parameters> FitClip(std::shared_ptr<const EyeRegionModel> model, const TrackedClip& clip,
                                double* warm_seconds = nullptr) {
  auto pool = std::make_shared<ThreadPool>();
  Fitter fresh(model, FitOptions{}, pool);
  Fitter warm(model, GazeTrackerOptions().SettledWarm(), pool);
  std::vector<Parameters> fits = {fresh.FitFace(clip.frames[0], clip.camera, clip.faces[0]).phi};
  Timer timer;
  for (std::size_t i = 1; i < clip.frames.size(); ++i) {
    fits.push_back(warm.FitFace(clip.frames[i], clip.camera, clip.faces[i], &fits.back()).phi);
  }
  if (warm_seconds != nullptr) *warm_seconds = timer.Seconds();
  return fits;
}

}  // namespace

double MeasureFitFps(std::shared_ptr<const EyeRegionModel> model, const TrackedClip& clip) {
  if (clip.frames.size() < 2) return 0;
  double seconds = 0;
  FitClip(model, clip, &seconds);
  return (clip.frames.size() - 1) / seconds;
}

double MeasureTrackFps(std::shared_ptr<const EyeRegionModel> model, std::shared_ptr<const LandmarkDetector> landmarks,
                       const MeanFace& mean_face, const std::filesystem::path& video, int max_frames) {
  GazeTracker tracker(model, landmarks, mean_face);
  Timer timer;
  VideoReader reader(video);
  const Camera camera = Camera::Default(reader.info().width, reader.info().height);
  long frames = 0;
  {
    TrackedFrameReader tracked_frames(reader, tracker, camera);
    TrackedFrame frame;
    while (frames < max_frames && tracked_frames.Next(frame)) {
      tracker.FitFaces(frame.image, frame.timestamp_s, camera, frame.faces);
      ++frames;
    }
  }  // with the frame read ahead
  return frames / timer.Seconds();
}

double MeasureRedirectFps(std::shared_ptr<const EyeRegionModel> model, const TrackedClip& clip) {
  if (clip.frames.empty()) return 0;
  const std::vector<Parameters> fits = FitClip(model, clip);
  Redirector redirector(model);
  cv::Mat frame;
  clip.frames[0].copyTo(frame);
  redirector.options().environment = redirector.Redirect(frame, clip.camera, fits[0], Retarget(fits[0], GazeTarget::Camera())).environment;
  Timer timer;
  for (std::size_t i = 0; i < clip.frames.size(); ++i) {
    clip.frames[i].copyTo(frame);
    redirector.Redirect(frame, clip.camera, fits[i], Retarget(fits[i], GazeTarget::Camera()));
  }
  return clip.frames.size() / timer.Seconds();
}

}  // namespace gazedirector
