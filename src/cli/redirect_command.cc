// gazedirector redirect: change where the people in an image or video look.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "cli/batch.h"
#include "cli/common.h"
#include "cli/fitting.h"
#include "gazedirector/fit/iris_alignment.h"
#include "gazedirector/io/fit_io.h"
#include "gazedirector/io/image_io.h"
#include "gazedirector/io/media.h"
#include "gazedirector/io/text_writer.h"
#include "gazedirector/io/video_reader.h"
#include "gazedirector/io/video_writer.h"
#include "gazedirector/video/tracked_frame_reader.h"
#include "gazedirector/redirect/gaze_script.h"
#include "gazedirector/redirect/redirector.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/interrupt.h"
#include "gazedirector/util/progress.h"
#include "gazedirector/viz/draw_fit.h"

namespace gazedirector::cli {
namespace {

// Fitted irises more than this many iris radii from the photo's own are left
// alone: in session 56, d10 and d14 frames above 0.6 redirected to the camera
// showed broken irises (white patches, a second iris edge) in every case
// looked at, while fits on the iris read 0.1-0.45; d3's frames at 0.6-0.7
// (narrowed eyes, two glances) redirected acceptably, so the line is 0.7.
constexpr double kDefaultMaxIrisOffset = 0.7;

struct RedirectCommandOptions {
  CommonOptions common;
  CameraOptions camera;
  FittingOptions fitting;
  BatchInputOptions batch;          // the inputs as given: files, or folders of them
  std::string input;                // the one being redirected
  std::string output;
  std::string look_at;
  std::vector<double> gaze;
  std::string frame = "camera";
  std::vector<double> offset;
  std::string script;
  std::string fits;
  std::string debug_dir;
  std::vector<long> debug_frames;
  bool side_by_side = false;
  bool rendered_eyeballs = false;
  bool no_eyelids = false;
  bool refit = false;
  double max_iris_offset = kDefaultMaxIrisOffset;
};

GazeScript ParseTarget(const RedirectCommandOptions& options) {
  const int given = !options.look_at.empty() + !options.gaze.empty() + !options.offset.empty() + !options.script.empty();
  if (given > 1) Fail(ExitCode::kUsage, "give one target: --look-at, --gaze, --offset or --script");
  if (!options.script.empty()) return GazeScript::Load(options.script);
  if (!options.gaze.empty()) {
    return GazeScript::Constant(GazeTarget::Direction(
        options.gaze[0], options.gaze[1], options.frame == "head" ? GazeTarget::Frame::kHead : GazeTarget::Frame::kCamera));
  }
  if (!options.offset.empty()) return GazeScript::Constant(GazeTarget::Offset(options.offset[0], options.offset[1]));
  if (options.look_at.empty() || options.look_at == "camera") {
    if (options.look_at.empty()) spdlog::info("no target given: eye contact (--look-at camera)");
    return GazeScript::Constant(GazeTarget::Camera());
  }
  std::istringstream stream(options.look_at);
  double x = 0, y = 0, z = 0;
  char c1 = 0, c2 = 0;
  if (!(stream >> x >> c1 >> y >> c2 >> z) || c1 != ',' || c2 != ',' || !stream.eof() || z == 0) {
    Fail(ExitCode::kUsage, "--look-at {}: expected \"camera\" or x,y,z in millimetres (camera frame, z not 0)", options.look_at);
  }
  return GazeScript::Constant(GazeTarget::Point({x, y, z}));
}

RedirectOptions MakeRedirectOptions(const RedirectCommandOptions& options) {
  RedirectOptions redirect;
  redirect.transfer_eyeballs = !options.rendered_eyeballs;
  redirect.warp_eyelids = !options.no_eyelids;
  return redirect;
}

cv::Mat SideBySide(const cv::Mat& before, const cv::Mat& after) {
  cv::Mat both;
  cv::hconcat(before, after, both);
  return both;
}

void WriteDebug(const std::filesystem::path& dir, const std::string& prefix, const cv::Mat& image, const Camera& camera,
                const Parameters& phi, bool good, const RedirectLayers& layers, const RedirectReport& report,
                Renderer& renderer, const std::vector<std::filesystem::path>& inputs) {
  cv::Mat overlay = image.clone();
  DrawFit(overlay, camera, phi, good, {true, true}, renderer);
  WriteImage(dir / (prefix + "fit_overlay.png"), overlay, inputs);
  if (layers.flow.empty()) return;
  double longest = 1;
  for (int y = 0; y < layers.flow.rows; ++y) {
    for (int x = 0; x < layers.flow.cols; ++x) {
      const cv::Vec2f f = layers.flow.at<cv::Vec2f>(y, x);
      longest = std::max(longest, std::hypot(double(f[0]), double(f[1])));
    }
  }
  WriteImage(dir / (prefix + "flow.png"), FlowPicture(layers.flow, longest), inputs);
  WriteImage(dir / (prefix + "skin_mask.png"), layers.skin_mask, inputs);
  WriteImage(dir / (prefix + "eyeball_mask.png"), layers.eyeball_mask, inputs);
  WriteImage(dir / (prefix + "transfer_mask.png"), layers.transfer_mask, inputs);
  WriteImage(dir / (prefix + "sclera_mask.png"), layers.sclera_mask, inputs);
  WriteImage(dir / (prefix + "eyeball_layer.png"), layers.eyeball_layer, inputs);
  WriteImage(dir / (prefix + "specular.png"), layers.specular, inputs);
  if (report.environment >= 0) {
    WriteImage(dir / (prefix + "environment.png"), BuiltInEnvironmentMaps()[report.environment].Picture(), inputs);
  }
}

// The video frames that get debugging pictures: those listed (--debug-frames),
// else ten spread evenly over the video (every frame of a shorter one).
class DebugFrameChoice {
 public:
  DebugFrameChoice(const std::vector<long>& listed, long frame_count)
      : frames_(listed.begin(), listed.end()), listed_(!listed.empty()) {
    if (listed_) return;
    const long count = std::max(frame_count, 1L);
    const long chosen = std::min(count, kDefaultFrames);
    for (long k = 0; k < chosen; ++k) frames_.insert(chosen == 1 ? 0 : std::lround(k * (count - 1.0) / (chosen - 1)));
  }
  bool Wants(long index) const { return frames_.contains(index); }
  // The listed frames after `last_index`, which the video does not reach.
  std::vector<long> ListedAfter(long last_index) const {
    if (!listed_) return {};
    return {frames_.upper_bound(last_index), frames_.end()};
  }

 private:
  static constexpr long kDefaultFrames = 10;
  std::set<long> frames_;
  bool listed_;
};

std::string EyeList(const std::array<bool, 2>& eyes) {
  if (eyes[0] && eyes[1]) return "both eyes";
  if (eyes[0]) return "left eye";
  if (eyes[1]) return "right eye";
  return "no eye";
}

bool IrisOffTooFar(double offset, const RedirectCommandOptions& options) {
  return options.max_iris_offset > 0 && offset > options.max_iris_offset;
}

// A still's fits: from --fits, else fitted now.
std::vector<StoredFit> FitsOfImage(const RedirectCommandOptions& options, const FittingSetup& setup,
                                   const cv::Mat& image, const Camera& camera) {
  std::vector<StoredFit> fits;
  if (!options.fits.empty()) {
    const FitsFile file = ReadFits(options.fits);
    RequireFitsOfSize(file, image.cols, image.rows);
    if (file.frames.size() > 1) {
      spdlog::warn("{} holds the fits of {} video frames; using the first one's", options.fits, file.frames.size());
    }
    fits = file.frames.begin()->second.faces;
  } else {
    for (const FaceFit& fit : setup.FitImage(image, camera)) fits.push_back(StoredFit::Of(fit));
  }
  if (fits.empty()) Fail(ExitCode::kNoFace, "no face found in {}; nothing to redirect", options.input);
  return fits;
}

// Says which of the script's segments start after a video ends, or, for an
// image (no duration), after 0 s: an image is redirected to the script's first moment.
void WarnOfUnseenSegments(const GazeScript& script, std::optional<double> video_duration_s) {
  std::vector<std::string> unseen;
  for (const double start : script.StartTimes()) {
    const bool seen = video_duration_s ? start < *video_duration_s : start <= 0;
    if (!seen) unseen.push_back(fmt::format("{:g} s", start));
  }
  if (unseen.empty()) return;
  const std::string segments =
      fmt::format("the gaze script's segment{} starting at {}", unseen.size() == 1 ? "" : "s", fmt::join(unseen, ", "));
  if (video_duration_s) {
    spdlog::warn("the video ends at {:.1f} s, so {} will not be seen", *video_duration_s, segments);
  } else {
    spdlog::warn("an image takes the gaze script's target at 0 s, so {} {} not used", segments,
                 unseen.size() == 1 ? "is" : "are");
  }
}

int RunOnImage(const RedirectCommandOptions& options, const FittingSetup& setup, const GazeScript& script) {
  const std::vector<std::filesystem::path> inputs = {options.input};
  const SourceImage source = ReadSourceImage(options.input);
  const cv::Mat& image = source.bgr;
  const Camera camera = options.camera.Resolve(image.cols, image.rows);
  WarnOfUnseenSegments(script, std::nullopt);
  const std::vector<StoredFit> fits = FitsOfImage(options, setup, image, camera);

  cv::Mat result = image.clone();
  Redirector redirector(setup.model(), MakeRedirectOptions(options));
  Renderer renderer(setup.model());
  int redirected = 0;
  for (const StoredFit& fit : fits) {
    if (!fit.good) {
      spdlog::warn("face {}: left untouched: the fit is poor ({})", fit.face_id, fit.note);
      continue;
    }
    const double offset = WorstIrisMisalignment(image, camera, fit.phi, fit.eyes, renderer);
    if (IrisOffTooFar(offset, options)) {
      spdlog::warn("face {}: left untouched: a fitted iris sits {:.2f} iris radii from the photo's (over "
                   "--max-iris-offset {:g}); redirected it would show a broken iris",
                   fit.face_id, offset, options.max_iris_offset);
      continue;
    }
    const Parameters target = script.TargetAt(fit.phi, 0);
    RedirectLayers layers;
    const RedirectReport report = redirector.Redirect(result, camera, fit.phi, target, options.debug_dir.empty() ? nullptr : &layers);
    if (!options.debug_dir.empty()) {
      WriteDebug(options.debug_dir, fits.size() > 1 ? fmt::format("face{}_", fit.face_id) : "", image, camera, fit.phi,
                 fit.good, layers, report, renderer, inputs);
    }
    if (!report.redirected[0] && !report.redirected[1]) {
      spdlog::warn("face {}: left untouched: {}", fit.face_id, report.note);
      continue;
    }
    if (AtTheEyesReach(target)) {
      spdlog::warn("face {}: {} lies beyond the eyes' reach ({}); they look as far toward it as they can",
                   fit.face_id, script.Describe(), ReachDescription());
    }
    ++redirected;
    spdlog::info("face {}: {} redirected from pitch {:.1f} yaw {:.1f} to pitch {:.1f} yaw {:.1f} deg (head frame), "
                 "reflections of the {} map{}{}",
                 fit.face_id, EyeList(report.redirected), fit.phi.gaze_pitch(), fit.phi.gaze_yaw(), target.gaze_pitch(),
                 target.gaze_yaw(), BuiltInEnvironmentMaps()[std::max(0, report.environment)].name,
                 report.specular_gain > 0 ? "" : " (none needed)", report.note.empty() ? "" : "; " + report.note);
  }
  result = InSourceFormat(source, result, options.output);
  if (options.side_by_side) result = SideBySide(InSourceFormat(source, image, options.output), result);
  WriteImage(options.output, result, PhotoMetadata::Read(options.input), inputs);
  spdlog::info("{}{} of {} face{} redirected to {} -> {}", LogLabel(options.input), redirected, fits.size(),
               fits.size() == 1 ? "" : "s", script.Describe(), options.output);
  return 0;
}

// Where one-go video redirection keeps its fits, so that a re-run reuses them.
std::filesystem::path FitsCachePath(const std::string& output) { return output + ".fits.jsonl"; }

nlohmann::json InputSignature(const std::filesystem::path& input) {
  return {{"input_bytes", std::filesystem::file_size(input)},
          {"input_mtime", std::filesystem::last_write_time(input).time_since_epoch().count()}};
}

// The fits (frame, face) held as they were because a fitted iris sits off
// the photo's by more than --max-iris-offset; the fits alone do not tell,
// the frames do.
using FitKey = std::pair<long, int>;
void AddFitsWithIrisOff(const RedirectCommandOptions& options, const cv::Mat& frame, long index,
                        const std::vector<StoredFit>& fits, const Camera& camera, Renderer& renderer,
                        std::set<FitKey>& off) {
  if (options.max_iris_offset <= 0) return;
  for (const StoredFit& fit : fits) {
    if (!fit.eyes_closed && IrisOffTooFar(WorstIrisMisalignment(frame, camera, fit.phi, fit.eyes, renderer), options)) {
      off.insert({index, fit.face_id});
    }
  }
}

[[noreturn]] void FailNoFaceInVideo(std::size_t frames, const std::string& input) {
  Fail(ExitCode::kNoFace, "no face found in any of the {} frames of {}; nothing to redirect", frames, input);
}

// Tracks the video into `fits_path` and returns what it wrote; finds the
// fits with an iris off on the way (`iris_off`), while each frame is at hand.
// A video without a face fails before its fits are kept: they hold nothing.
FitsFile TrackVideo(const RedirectCommandOptions& options, const FittingSetup& setup, const Camera& camera,
                    const std::filesystem::path& fits_path, std::set<FitKey>& iris_off) {
  const std::vector<std::filesystem::path> inputs = {options.input};
  VideoReader reader(options.input);
  GazeTracker tracker = setup.MakeTracker();
  Renderer renderer(setup.model());
  TextWriter json(fits_path, inputs);
  Progress progress("track", reader.info().frame_count, "frames", options.common.quiet);
  std::size_t frames = 0;
  bool any_face = false;
  TrackedFrameReader tracked_frames(reader, tracker, camera);
  TrackedFrame frame;
  while (tracked_frames.Next(frame)) {
    ++frames;
    ThrowIfInterrupted();
    const std::vector<FaceFit> fits = tracker.FitFaces(frame.image, frame.timestamp_s, camera, frame.faces);
    any_face = any_face || !fits.empty();
    std::vector<StoredFit> stored;
    for (const FaceFit& fit : fits) stored.push_back(StoredFit::Of(fit));
    AddFitsWithIrisOff(options, frame.image, frame.index, stored, camera, renderer, iris_off);
    nlohmann::json record = FrameRecord(frame.index, frame.timestamp_s, fits, frame.index == 0 ? &camera : nullptr);
    if (frame.index == 0) record["source"] = InputSignature(options.input);
    json.stream() << record.dump() << '\n';
    progress.Update(frame.index + 1);
  }
  progress.Finish();
  if (!any_face) FailNoFaceInVideo(frames, options.input);
  json.Finish();
  return ReadFits(fits_path);
}

bool CacheMatches(const std::filesystem::path& fits_path, const std::filesystem::path& input) {
  std::ifstream stream(fits_path);
  std::string first;
  if (!stream || !std::getline(stream, first)) return false;
  try {
    const nlohmann::json record = nlohmann::json::parse(first);
    return record.contains("source") && record["source"] == InputSignature(input);
  } catch (const nlohmann::json::exception&) {
    return false;
  }
}

// The fits with an iris off (AddFitsWithIrisOff) among fits made earlier: a
// pass over the video's frames.
std::set<FitKey> FitsWithIrisOff(const RedirectCommandOptions& options, const FitsFile& fits, const Camera& camera,
                                 std::shared_ptr<const EyeRegionModel> model) {
  std::set<FitKey> off;
  if (options.max_iris_offset <= 0) return off;
  VideoReader reader(options.input);
  Renderer renderer(std::move(model));
  Progress progress("check fits", reader.info().frame_count, "frames", options.common.quiet);
  cv::Mat frame;
  while (reader.Read(frame)) {
    ThrowIfInterrupted();
    const long index = reader.frame_index();
    const auto stored = fits.frames.find(index);
    if (stored != fits.frames.end()) AddFitsWithIrisOff(options, frame, index, stored->second.faces, camera, renderer, off);
    progress.Update(index + 1);
  }
  progress.Finish();
  return off;
}

// Per face and frame, how much of the redirection to apply: 0 while an eye
// is closed (blinks are kept as they were) or a fitted iris is off the
// photo's by more than --max-iris-offset (kept rather than broken), easing
// back to 1 over `handover_s` on either side.
std::map<long, std::map<int, double>> RedirectionWeights(const FitsFile& fits, double handover_s, double closed_deg,
                                                         const std::set<FitKey>& iris_off) {
  std::map<int, std::vector<double>> held_times;  // by face, in frame order
  for (const auto& [index, frame] : fits.frames) {
    for (const StoredFit& fit : frame.faces) {
      if (fit.eyes_closed || iris_off.contains({index, fit.face_id}) || fit.phi.eyelid_closure() > closed_deg) {
        held_times[fit.face_id].push_back(frame.timestamp_s);
      }
    }
  }
  std::map<long, std::map<int, double>> weights;
  for (const auto& [index, frame] : fits.frames) {
    for (const StoredFit& fit : frame.faces) {
      double nearest = 1e9;
      const std::vector<double>& held = held_times[fit.face_id];
      auto it = std::lower_bound(held.begin(), held.end(), frame.timestamp_s);
      if (it != held.end()) nearest = std::min(nearest, *it - frame.timestamp_s);
      if (it != held.begin()) nearest = std::min(nearest, frame.timestamp_s - *std::prev(it));
      const double t = std::clamp(nearest / handover_s, 0.0, 1.0);
      weights[index][fit.face_id] = t * t * (3 - 2 * t);
    }
  }
  return weights;
}

// A video's fits: given (--fits), stored by an earlier run, or tracked now;
// `iris_off` is filled where tracking found them on the way.
FitsFile FitsOfVideo(const RedirectCommandOptions& options, const FittingSetup& setup, const Camera& camera,
                     std::optional<std::set<FitKey>>& iris_off) {
  if (!options.fits.empty()) {
    FitsFile fits = ReadFits(options.fits);
    spdlog::info("using the fits in {} ({} frames)", options.fits, fits.frames.size());
    return fits;
  }
  const std::filesystem::path cache = FitsCachePath(options.output);
  if (!options.refit && std::filesystem::exists(cache) && CacheMatches(cache, options.input)) {
    spdlog::info("reusing the fits stored in {} (--refit to track again)", cache.string());
    return ReadFits(cache);
  }
  FitsFile fits = TrackVideo(options, setup, camera, cache, iris_off.emplace());
  spdlog::info("fits stored in {}; edit them and pass --fits to re-render", cache.string());
  return fits;
}

int RunOnVideo(const RedirectCommandOptions& options, const FittingSetup& setup, const GazeScript& script) {
  const std::vector<std::filesystem::path> inputs = {options.input};
  VideoReader reader(options.input);
  const VideoInfo& info = reader.info();
  const Camera camera = options.camera.Resolve(info.width, info.height);
  WarnOfUnseenSegments(script, info.duration_s());

  // Stage 1: the fits, and the faces and frames held as they were.
  std::optional<std::set<FitKey>> iris_off;  // found while tracking, else in a pass of their own
  const FitsFile fits = FitsOfVideo(options, setup, camera, iris_off);
  RequireFitsOfSize(fits, info.width, info.height);
  const bool any_face = std::any_of(fits.frames.begin(), fits.frames.end(),
                                    [](const auto& frame) { return !frame.second.faces.empty(); });
  if (!any_face) FailNoFaceInVideo(fits.frames.size(), options.input);
  const RedirectOptions redirect_options = MakeRedirectOptions(options);
  if (!iris_off) iris_off = FitsWithIrisOff(options, fits, camera, setup.model());
  const auto weights = RedirectionWeights(fits, 0.15, 0.5 * redirect_options.max_closure_deg, *iris_off);

  // Stage 2: re-render every frame.
  const int out_width = options.side_by_side ? 2 * info.width : info.width;
  VideoWriter writer(options.output, WriterOptionsFor(options.input, info, out_width), inputs);
  Redirector redirector(setup.model(), redirect_options);
  std::map<int, int> environments;  // chosen once per face, so reflections do not flicker
  Progress progress("redirect", info.frame_count, "frames", options.common.quiet);
  DebugFrameChoice debug_choice(options.debug_frames, info.frame_count);
  std::optional<Renderer> debug_renderer;
  if (!options.debug_dir.empty()) debug_renderer.emplace(setup.model());
  cv::Mat frame;
  long redirected_frames = 0, untouched = 0, beyond_reach = 0, debugged_frames = 0;
  while (reader.Read(frame)) {
    ThrowIfInterrupted();
    const long index = reader.frame_index();
    const double time = reader.timestamp_s();
    cv::Mat result = frame.clone();
    const auto stored = fits.frames.find(index);
    const bool debug = debug_renderer && debug_choice.Wants(index);
    bool any = false, pictured = false;
    if (stored != fits.frames.end()) {
      const std::size_t faces = stored->second.faces.size();
      for (const StoredFit& fit : stored->second.faces) {
        RedirectLayers layers;  // stays empty for a face left as it was: its pictures are the overlay alone
        RedirectReport report;
        const auto write_debug = [&] {
          if (!debug) return;
          const std::string prefix =
              fmt::format("frame{:05d}_{}", index, faces > 1 ? fmt::format("face{}_", fit.face_id) : "");
          WriteDebug(options.debug_dir, prefix, frame, camera, fit.phi, fit.good, layers, report, *debug_renderer, inputs);
          pictured = true;
        };
        if (!fit.good) {
          ++untouched;
          write_debug();
          continue;
        }
        const double weight = weights.at(index).at(fit.face_id);
        if (weight <= 0) {  // a blink or an iris off the photo's: keep the original
          write_debug();
          continue;
        }
        const Parameters scripted = script.TargetAt(fit.phi, time);
        const Parameters target = BlendGaze(fit.phi, scripted, weight);
        const auto chosen = environments.find(fit.face_id);
        redirector.options().environment = chosen == environments.end() ? -1 : chosen->second;
        report = redirector.Redirect(result, camera, fit.phi, target, debug ? &layers : nullptr);
        write_debug();
        if (report.redirected[0] || report.redirected[1]) {
          any = true;
          beyond_reach += AtTheEyesReach(scripted) ? 1 : 0;
          if (chosen == environments.end()) environments[fit.face_id] = report.environment;
        }
      }
    }
    redirected_frames += any ? 1 : 0;
    debugged_frames += pictured ? 1 : 0;
    writer.Write(options.side_by_side ? SideBySide(frame, result) : result, time);
    progress.Update(index + 1);
  }
  progress.Finish();
  WarnIfTruncated(reader, options.input);
  writer.Finish();
  if (debug_renderer) {
    const std::vector<long> unseen = debug_choice.ListedAfter(reader.frame_index());
    if (!unseen.empty()) {
      spdlog::warn("--debug-frames: the video ends at frame {}, so frame{} {} had no pictures", reader.frame_index(),
                   unseen.size() == 1 ? "" : "s", fmt::join(unseen, ", "));
    }
    spdlog::info("debugging pictures of {} frame{} in {}", debugged_frames, debugged_frames == 1 ? "" : "s",
                 options.debug_dir);
  }
  if (beyond_reach > 0) {
    spdlog::warn("for {} redirected face{} across the frames the target lay beyond the eyes' reach ({}); they looked "
                 "as far toward it as they could",
                 beyond_reach, beyond_reach == 1 ? "" : "s", ReachDescription());
  }
  spdlog::info("{}{} of {} frames redirected to {} ({} poor fits and {} with an iris off the photo's left "
               "untouched) -> {}",
               LogLabel(options.input), redirected_frames, reader.frame_index() + 1, script.Describe(), untouched, iris_off->size(),
               options.output);
  return 0;
}

// Options that mean nothing for this kind of input are said to be ignored
// rather than dropped silently.
void WarnOfOptionsForTheOtherKind(const RedirectCommandOptions& options, MediaKind kind) {
  if (kind == MediaKind::kImage && !options.debug_frames.empty()) {
    spdlog::warn("--debug-frames chooses a video's frames; an image's debugging pictures are written whatever it lists");
  }
  if (kind == MediaKind::kImage && options.refit) {
    spdlog::warn("--refit: an image is fitted anew on every run unless --fits is given, so it changes nothing here");
  }
}

void RequireFitsFile(const RedirectCommandOptions& options) {
  if (!options.fits.empty() && !std::filesystem::exists(options.fits)) {
    Fail(ExitCode::kBadInput, "--fits {}: no such file", options.fits);
  }
}

int RunOnOne(RedirectCommandOptions options) {
  options.input = options.batch.inputs.front();
  const MediaKind kind = DetectMediaKind(options.input);
  RequireOutputKind(options.output, "-o", kind, options.input);
  WarnOfOptionsForTheOtherKind(options, kind);
  RequireWritableFolder(options.debug_dir, "--debug-dir");
  RequireFitsFile(options);
  const GazeScript script = ParseTarget(options);
  const FittingSetup setup = FittingSetup::Create(options.common, options.fitting);
  return kind == MediaKind::kImage ? RunOnImage(options, setup, script) : RunOnVideo(options, setup, script);
}

// Several inputs, or folders of them: each redirected into the folder -o
// names, as a run on it alone redirects it, the model loaded once. Every
// input and output is checked before any work.
int RunBatch(const RedirectCommandOptions& options) {
  namespace fs = std::filesystem;
  if (!options.fits.empty()) Fail(ExitCode::kUsage, "--fits holds one input's fits: give it with one input");
  options.camera.Check();
  RequireFolderName(options.output, "-o");
  const std::vector<BatchInput> inputs = ExpandBatchInputs(options.batch, {options.output, options.debug_dir});
  std::vector<fs::path> outputs;
  for (const BatchInput& input : inputs) outputs.push_back(BatchOutputPath(options.output, input));
  RequireDistinctOutputs(inputs, outputs);
  RequireWritableFolder(options.output, "-o");
  RequireWritableFolder(options.debug_dir, "--debug-dir");
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    RequireOutputKind(outputs[i].string(), "-o", inputs[i].kind, inputs[i].path.string());
  }
  const bool any_video =
      std::any_of(inputs.begin(), inputs.end(), [](const BatchInput& input) { return input.kind == MediaKind::kVideo; });
  WarnOfOptionsForTheOtherKind(options, any_video ? MediaKind::kVideo : MediaKind::kImage);
  const GazeScript script = ParseTarget(options);
  const FittingSetup setup = FittingSetup::Create(options.common, options.fitting);
  return RunEachInput(inputs, [&](std::size_t i) {
    RedirectCommandOptions one = options;
    one.input = inputs[i].path.string();
    one.output = outputs[i].string();
    if (!options.debug_dir.empty()) one.debug_dir = (fs::path(options.debug_dir) / inputs[i].name).string();
    RequireWritableFolder(one.debug_dir, "--debug-dir");
    return inputs[i].kind == MediaKind::kImage ? RunOnImage(one, setup, script) : RunOnVideo(one, setup, script);
  });
}

int RunRedirect(const RedirectCommandOptions& options) {
  ApplyLogLevel(options.common);
  return IsBatch(options.batch.inputs, options.output) ? RunBatch(options) : RunOnOne(options);
}

}  // namespace

Command RegisterRedirectCommand(CLI::App& root) {
  auto options = std::make_shared<RedirectCommandOptions>();
  CLI::App* app = root.add_subcommand("redirect", "Change where the people in an image or video look");
  AddBatchInputOptions(*app, options->batch);
  app->add_option("-o,--output", options->output,
                  "Output image or video; for several inputs (or a folder) a folder, where each keeps its name")
      ->required();
  app->add_option("--look-at", options->look_at, "Look at \"camera\" (eye contact, the default) or a point x,y,z (mm, camera frame)");
  app->add_option("--gaze", options->gaze, "Look in a direction: pitch,yaw in degrees (up and image-right +)")
      ->expected(2)->delimiter(',');
  app->add_option("--frame", options->frame, "The frame of --gaze: camera or head")
      ->check(CLI::IsMember({"camera", "head"}))->capture_default_str();
  app->add_option("--offset", options->offset, "Change the fitted gaze by dpitch,dyaw degrees")->expected(2)->delimiter(',');
  app->add_option("--script", options->script, "A JSON timeline of gaze targets (videos)");
  app->add_option("--fits", options->fits, "Fits from `gazedirector track` (perhaps edited) instead of tracking now");
  app->add_flag("--side-by-side", options->side_by_side, "Write the original and the result side by side");
  CLI::Option* debug_dir = app->add_option(
      "--debug-dir", options->debug_dir,
      "Write the fit overlay, flow field, masks and eyeball layer here (for a video: of the frames --debug-frames "
      "chooses, named frameNNNNN_...)");
  app->add_option("--debug-frames", options->debug_frames,
                  "The video frames (0-based indices, comma-separated) that --debug-dir pictures; default: ten spread "
                  "evenly over the video")
      ->delimiter(',')
      ->check(CLI::NonNegativeNumber)
      ->needs(debug_dir);
  app->add_flag("--rendered-eyeballs", options->rendered_eyeballs, "Use only rendered eyeballs (the paper), not the photo's own iris");
  app->add_flag("--no-eyelids", options->no_eyelids, "Move only the eyeballs, not the eyelids");
  app->add_flag("--refit", options->refit, "Track the video again even when stored fits exist");
  app->add_option("--max-iris-offset", options->max_iris_offset,
                  "Leave a face as it was (in a video: those frames, eased in and out) where a fitted iris sits more "
                  "than this many iris radii from the photo's own (as `eval iris` measures); 0: never")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  AddFittingOptions(*app, options->fitting);
  AddCameraOptions(*app, options->camera);
  AddCommonOptions(*app, options->common);
  return {app, [options] { return RunRedirect(*options); }};
}

}  // namespace gazedirector::cli
