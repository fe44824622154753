#include "gazedirector/eval/performance.h"

#include "gazedirector/io/video_reader.h"
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

}  // namespace gazedirector
