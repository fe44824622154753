// gazedirector eval iris: how far the fitted irises sit from the photo's own.
#include <cmath>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/eval_options.h"
#include "gazedirector/fit/iris_alignment.h"
#include "gazedirector/io/fit_io.h"
#include "gazedirector/io/image_io.h"
#include "gazedirector/io/text_writer.h"
#include "gazedirector/io/video_reader.h"
#include "gazedirector/render/renderer.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/interrupt.h"
#include "gazedirector/util/progress.h"
#include "gazedirector/util/statistics.h"
#include "gazedirector/video/gaze_tracker.h"

namespace gazedirector::cli {
namespace {

// The fits of one frame: read from a fits file, or tracked now.
std::vector<StoredFit> FitsOfFrame(const std::optional<FitsFile>& stored, long index, const cv::Mat& frame,
                                   double timestamp_s, const Camera& camera, GazeTracker& tracker, bool video) {
  if (stored) {
    const auto found = stored->frames.find(index);
    return found == stored->frames.end() ? std::vector<StoredFit>() : found->second.faces;
  }
  std::vector<StoredFit> fits;
  const std::vector<FaceFit> tracked = video ? tracker.ProcessFrame(frame, timestamp_s, camera) : tracker.ProcessImage(frame, camera);
  for (const FaceFit& fit : tracked) fits.push_back(StoredFit::Of(fit));
  return fits;
}

}  // namespace

int RunIrisEval(const EvalOptions& options) {
  ApplyLogLevel(options.common);
  const MediaKind kind = DetectMediaKind(options.iris_input);
  RequireCsvOutput(options.csv, {options.iris_input});
  std::optional<FitsFile> stored;
  if (!options.iris_fits.empty()) stored = ReadFits(options.iris_fits);
  const FittingSetup setup = FittingSetup::Create(options.common, options.fitting);
  GazeTracker tracker = setup.MakeTracker();
  Renderer renderer(setup.model());
  std::optional<CsvWriter> csv;
  if (!options.csv.empty()) {
    csv.emplace(options.csv, std::vector<std::string>{"frame", "face_id", "eye", "iris_misalignment"},
                std::vector<std::filesystem::path>{options.iris_input});
  }
  std::vector<double> distances;
  long frames = 0, evaluated = 0;
  auto evaluate = [&](const cv::Mat& frame, long index, double timestamp_s, const Camera& camera) {
    const std::vector<StoredFit> fits = FitsOfFrame(stored, index, frame, timestamp_s, camera, tracker, kind == MediaKind::kVideo);
    if (index % options.every != 0) return;
    ++evaluated;
    for (const StoredFit& fit : fits) {
      if (fit.eyes_closed) continue;
      const std::array<double, 2> misalignment = IrisMisalignment(frame, camera, fit.phi, fit.eyes, renderer);
      for (int eye = 0; eye < 2; ++eye) {
        if (!std::isfinite(misalignment[eye])) continue;
        distances.push_back(misalignment[eye]);
        if (csv) {
          csv->AddRow({std::to_string(index), std::to_string(fit.face_id), eye == kLeftEye ? "left" : "right",
                       fmt::format("{:.4f}", misalignment[eye])});
        }
      }
    }
  };
  auto camera_for = [&](int width, int height) {
    if (stored) RequireFitsOfSize(*stored, width, height);
    return stored && stored->camera ? *stored->camera : options.camera.Resolve(width, height);
  };
  if (kind == MediaKind::kImage) {
    const cv::Mat image = ReadSourceImage(options.iris_input).bgr;
    evaluate(image, 0, 0.0, camera_for(image.cols, image.rows));
    frames = 1;
  } else {
    VideoReader reader(options.iris_input);
    const Camera camera = camera_for(reader.info().width, reader.info().height);
    Progress progress("eval iris", reader.info().frame_count, "frames", options.common.quiet || options.json);
    cv::Mat frame;
    while (reader.Read(frame)) {
      ThrowIfInterrupted();
      evaluate(frame, reader.frame_index(), reader.timestamp_s(), camera);
      progress.Update(reader.frame_index() + 1);
    }
    progress.Finish();
    frames = reader.frame_index() + 1;
  }
  if (distances.empty()) Fail(ExitCode::kNoFace, "no open fitted eye in {}", options.iris_input);
  if (csv) csv->Finish();
  const double median = Median(distances), p90 = Quantile(distances, 0.9), mean = Mean(distances);
  if (options.json) {
    fmt::print("{}\n", nlohmann::json{{"frames", frames}, {"frames_evaluated", evaluated}, {"eyes", distances.size()},
                                      {"median", median}, {"p90", p90}, {"mean", mean}}
                           .dump());
    return 0;
  }
  fmt::print("fitted iris to the photo's darkest eyeball pixels, in iris radii ({}; {} of {} frames, {} open eyes{})\n",
             options.iris_input, evaluated, frames, distances.size(), stored ? ", fits from " + options.iris_fits : "");
  fmt::print("  median {:.2f}   90th percentile {:.2f}   mean {:.2f}\n", median, p90, mean);
  fmt::print("  (about 0.1-0.4 on the iris; 1 or more: the fit lost it)\n");
  if (csv) fmt::print("each eye: {}\n", options.csv);
  return 0;
}

}  // namespace gazedirector::cli
