#include "gazedirector/eval/columbia.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <thread>

#include <spdlog/spdlog.h>

#include "gazedirector/fit/face_fit.h"
#include "gazedirector/geometry/rotation.h"
#include "gazedirector/io/assets.h"
#include "gazedirector/io/image_io.h"
#include "gazedirector/io/media.h"
#include "gazedirector/redirect/gaze_target.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/interrupt.h"
#include "gazedirector/util/statistics.h"
#include "gazedirector/util/thread_pool.h"
#include "gazedirector/util/timer.h"

namespace gazedirector {
namespace fs = std::filesystem;

int ColumbiaCrop::ModelEye() const { return eye == 'L' ? kRightEye : kLeftEye; }

double ColumbiaCrop::HeadYaw() const { return -head_pose; }

Eigen::Vector2d ColumbiaCrop::Label(GazeFrame frame) const {
  if (frame == GazeFrame::kCamera) return Eigen::Vector2d(vertical, horizontal);
  return EyeRegionModel::CameraGazeInHead(vertical, horizontal, HeadYaw());
}

std::string ColumbiaCrop::Photo() const {
  const std::string name = path.filename().string();
  return name.substr(0, name.size() - std::string("_L.jpg").size());
}

bool ParseColumbiaName(const fs::path& path, ColumbiaCrop& crop) {
  static const std::regex pattern(R"((\d{4})_2m_(-?\d+)P_(-?\d+)V_(-?\d+)H_([LR])\.jpg)");
  std::smatch match;
  const std::string name = path.filename().string();
  if (!std::regex_match(name, match, pattern)) return false;
  crop.path = path;
  crop.subject = match[1];
  crop.head_pose = std::stoi(match[2]);
  crop.vertical = std::stoi(match[3]);
  crop.horizontal = std::stoi(match[4]);
  crop.eye = match[5].str()[0];
  return true;
}

fs::path ColumbiaDirOrDefault(const std::string& dir) {
  return dir.empty() ? DefaultDataDir() / "columbia-eyes" : fs::path(dir);
}

namespace {

// Whether a crop can be read, from its JPEG or PNG header where it has one
// (whole and sized), else by decoding it: every crop is decoded later anyway,
// and a listing of thousands should not decode them all once more.
bool Readable(const fs::path& path) {
  try {
    if (const std::optional<ImageHeader> header = ProbeImageHeader(path)) {
      return header->complete && header->width > 0 && header->height > 0;
    }
    return !ReadImage(path).empty();
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

std::vector<ColumbiaCrop> ListColumbia(const fs::path& dir, std::vector<fs::path>* skipped) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) Fail(ExitCode::kBadInput, "{}: not a folder of Columbia crops", dir.string());
  std::vector<ColumbiaCrop> crops;
  std::vector<fs::path> others, unreadable, repeated;
  std::set<fs::path> names;
  for (const fs::path& path : FilesIn(dir, /*recursive=*/true)) {
    ColumbiaCrop crop;
    if (!ParseColumbiaName(path, crop)) {
      others.push_back(path);
    } else if (!names.insert(path.filename()).second) {
      repeated.push_back(path);
    } else if (!Readable(path)) {
      unreadable.push_back(path);
    } else {
      crops.push_back(crop);
    }
  }
  if (crops.empty() && unreadable.empty()) {
    Fail(ExitCode::kBadInput, "{}: no files named like 0001_2m_0P_0V_0H_L.jpg", dir.string());
  }
  if (crops.empty()) {
    Fail(ExitCode::kBadInput, "{}: none of its {} crop(s) can be read as an image (first: {})", dir.string(),
         unreadable.size(), unreadable.front().filename().string());
  }
  if (!others.empty()) {
    spdlog::warn("{}: skipped {} file(s) not named like 0001_2m_0P_0V_0H_L.jpg (first: {})", dir.string(),
                 others.size(), others.front().filename().string());
  }
  if (!unreadable.empty()) {
    spdlog::warn("{}: left out {} crop(s) that cannot be read as images (first: {})", dir.string(), unreadable.size(),
                 unreadable.front().filename().string());
  }
  if (!repeated.empty()) {
    spdlog::warn("{}: left out {} crop(s) whose name another folder holds too (first: {})", dir.string(),
                 repeated.size(), repeated.front().string());
  }
  if (skipped != nullptr) {
    others.insert(others.end(), unreadable.begin(), unreadable.end());
    others.insert(others.end(), repeated.begin(), repeated.end());
    *skipped = std::move(others);
  }
  return crops;
}

double GazeAngleBetween(double pitch_a, double yaw_a, double pitch_b, double yaw_b) {
  const Eigen::Vector3d a = EyeRegionModel::GazeInHead(pitch_a, yaw_a);
  const Eigen::Vector3d b = EyeRegionModel::GazeInHead(pitch_b, yaw_b);
  return RadToDeg(std::acos(std::clamp(a.dot(b), -1.0, 1.0)));
}

namespace {

GazeReading Read(double pitch, double yaw, const Eigen::Vector2d& label) {
  return {pitch, yaw, std::abs(pitch - label.x()), std::abs(yaw - label.y())};
}

const AppearanceGaze& ModelFor(const std::map<std::string, AppearanceGaze>& models, const std::string& subject) {
  const auto found = models.find(subject);
  if (found == models.end()) Fail(ExitCode::kInternal, "no appearance gaze model for subject {}", subject);
  return found->second;
}

}  // namespace

std::vector<ColumbiaPhoto> CombineEyes(const std::vector<ColumbiaFit>& fits) {
  std::vector<ColumbiaPhoto> photos;
  std::map<std::string, std::size_t> index_of_photo;
  for (const ColumbiaFit& fit : fits) {
    const auto [it, is_new] = index_of_photo.emplace(fit.crop.Photo(), photos.size());
    if (is_new) photos.emplace_back().crop = fit.crop;
    ColumbiaPhoto& photo = photos[it->second];
    photo.in_head.pitch += fit.in_head.pitch, photo.in_head.yaw += fit.in_head.yaw;
    photo.in_camera.pitch += fit.in_camera.pitch, photo.in_camera.yaw += fit.in_camera.yaw;
    ++photo.eyes;
  }
  for (ColumbiaPhoto& photo : photos) {
    photo.in_head = Read(photo.in_head.pitch / photo.eyes, photo.in_head.yaw / photo.eyes, photo.crop.Label(GazeFrame::kHead));
    photo.in_camera = Read(photo.in_camera.pitch / photo.eyes, photo.in_camera.yaw / photo.eyes,
                           photo.crop.Label(GazeFrame::kCamera));
  }
  return photos;
}

SubjectResampling ResampleSubjects(const std::vector<ColumbiaPhoto>& photos, GazeFrame frame, int draws,
                                   unsigned seed) {
  struct ErrorSums {
    double yaw = 0, pitch = 0;
    int photos = 0;
  };
  std::map<std::string, ErrorSums> by_subject;
  for (const ColumbiaPhoto& photo : photos) {
    const GazeReading& reading = photo.Reading(frame);
    ErrorSums& sums = by_subject[photo.crop.subject];
    sums.yaw += reading.yaw_error, sums.pitch += reading.pitch_error, ++sums.photos;
  }
  std::vector<ErrorSums> subjects;
  for (const auto& [subject, sums] : by_subject) subjects.push_back(sums);
  SubjectResampling result;
  result.subjects = static_cast<int>(subjects.size()), result.draws = draws;
  if (subjects.empty()) return result;
  std::mt19937 random(seed);
  std::uniform_int_distribution<std::size_t> pick(0, subjects.size() - 1);
  std::vector<double> yaw_means, pitch_means;
  for (int draw = 0; draw < draws; ++draw) {
    ErrorSums total;
    for (std::size_t i = 0; i < subjects.size(); ++i) {
      const ErrorSums& drawn = subjects[pick(random)];
      total.yaw += drawn.yaw, total.pitch += drawn.pitch, total.photos += drawn.photos;
    }
    yaw_means.push_back(total.yaw / total.photos);
    pitch_means.push_back(total.pitch / total.photos);
  }
  result.yaw_low = Quantile(yaw_means, 0.05), result.yaw_high = Quantile(yaw_means, 0.95);
  result.pitch_low = Quantile(pitch_means, 0.05), result.pitch_high = Quantile(pitch_means, 0.95);
  return result;
}

std::vector<HeadYawReadings> SummariseHeadYawReadings(const std::vector<ColumbiaFit>& fits) {
  // One reading per photo (both eyes carry the photo's), by head pose and subject.
  struct PoseReadings {
    double head_yaw = 0;
    std::map<std::string, std::vector<double>> by_subject;
  };
  std::map<int, PoseReadings> readings;
  std::set<std::string> photos_seen;
  for (const ColumbiaFit& fit : fits) {
    if (std::isnan(fit.appearance.head_yaw) || !photos_seen.insert(fit.crop.Photo()).second) continue;
    PoseReadings& pose = readings[fit.crop.head_pose];
    pose.head_yaw = fit.crop.HeadYaw();
    pose.by_subject[fit.crop.subject].push_back(fit.appearance.head_yaw);
  }
  std::vector<HeadYawReadings> summaries;
  for (const auto& [head_pose, pose] : readings) {
    HeadYawReadings& summary = summaries.emplace_back();
    summary.head_pose = head_pose;
    summary.subjects = static_cast<int>(pose.by_subject.size());
    const double head_yaw = pose.head_yaw;
    std::vector<double> subject_means;
    for (const auto& [subject, values] : pose.by_subject) {
      const double subject_mean = Mean(values);
      subject_means.push_back(subject_mean);
      for (const double reading : values) {
        summary.mean_reading += reading;
        summary.mean_abs_error += std::abs(reading - head_yaw);
        summary.within_subject += std::abs(reading - subject_mean);
        ++summary.photos;
      }
    }
    summary.mean_reading /= summary.photos;
    summary.mean_abs_error /= summary.photos;
    summary.within_subject /= summary.photos;
    summary.mean_error = summary.mean_reading - head_yaw;
    const double mean_of_means = Mean(subject_means);
    for (const double mean : subject_means) summary.subject_spread += std::pow(mean - mean_of_means, 2);
    summary.subject_spread = std::sqrt(summary.subject_spread / static_cast<double>(subject_means.size()));
  }
  return summaries;
}

void AddColumbiaCrops(const std::vector<ColumbiaCrop>& crops, AppearanceGazeTrainer& trainer) {
  for (const ColumbiaCrop& crop : crops) {
    // Read as the fits read it, so that training and reading see the same grey.
    const cv::Mat image = ReadImage(crop.path);
    const Eigen::Vector2d label = crop.Label(GazeFrame::kHead);
    trainer.Add(crop.subject, image, crop.ModelEye(), {label.x(), label.y(), crop.HeadYaw()});
  }
}

std::map<std::string, AppearanceGaze> LeaveSubjectOut(const AppearanceGazeTrainer& trainer,
                                                      const std::vector<std::string>& subjects) {
  // The subjects the trainer has no crops of (people kept aside, say) share
  // one model of all of them (left_out ""), solved once.
  std::vector<std::string> left_out;
  std::map<std::string, size_t> index_of_left_out, solve_of;
  for (const std::string& subject : subjects) {
    const std::string key = trainer.Has(subject) ? subject : std::string();
    const auto [entry, added] = index_of_left_out.emplace(key, left_out.size());
    if (added) left_out.push_back(key);
    solve_of[subject] = entry->second;
  }
  // Each solve is a few seconds of dense algebra on one core: side by side.
  std::vector<AppearanceGaze> solved(left_out.size());
  ThreadPool threads;
  threads.ParallelFor(static_cast<int>(left_out.size()),
                      [&](int index, int) { solved[index] = trainer.Solve(left_out[index]); });
  std::map<std::string, AppearanceGaze> models;
  std::vector<int> readers(left_out.size(), 0);
  for (const auto& [subject, index] : solve_of) ++readers[index];
  // Copied only while another subject still reads the same model.
  for (const auto& [subject, index] : solve_of) {
    models.emplace(subject, --readers[index] == 0 ? std::move(solved[index]) : solved[index]);
  }
  return models;
}

std::map<std::string, double> ReadHeadYawByPhoto(const std::vector<ColumbiaCrop>& crops,
                                                 const std::map<std::string, AppearanceGaze>& models) {
  std::map<std::string, std::pair<double, int>> sums;
  for (const ColumbiaCrop& crop : crops) {
    const AppearanceGaze& model = ModelFor(models, crop.subject);
    const cv::Mat image = ReadImage(crop.path);
    auto& [sum, count] = sums[crop.Photo()];
    sum += model.ReadHeadYaw(image, crop.ModelEye());
    ++count;
  }
  std::map<std::string, double> head_yaws;
  for (const auto& [photo, sum] : sums) head_yaws[photo] = sum.first / sum.second;
  return head_yaws;
}

std::vector<ColumbiaFit> FitColumbia(const std::vector<ColumbiaCrop>& crops, std::shared_ptr<const EyeRegionModel> model,
                                     const FitOptions& options, int threads, bool known_head_pose,
                                     const std::function<void(int)>& progress,
                                     const std::map<std::string, AppearanceGaze>* appearance) {
  std::vector<ColumbiaFit> fits(crops.size());
  const std::map<std::string, double> read_head_yaws = appearance != nullptr && !known_head_pose
                                                            ? ReadHeadYawByPhoto(crops, *appearance)
                                                            : std::map<std::string, double>{};
  std::atomic<int> next{0}, done{0};
  std::mutex progress_mutex;
  std::exception_ptr error;
  auto work = [&] {
    try {
      FitOptions recorded = options;
      recorded.record_history = true;
      if (known_head_pose) recorded.free[LayoutOf(Block::kRotation).offset + 1] = false;
      // One fitter per thread, each with a single worker: many small fits go
      // faster side by side than one at a time.
      Fitter fitter(model, recorded, std::make_shared<ThreadPool>(1));
      for (int i; (i = next++) < static_cast<int>(crops.size());) {
        if (InterruptRequested()) return;
        const ColumbiaCrop& crop = crops[i];
        const cv::Mat image = ReadImage(crop.path);
        Timer timer;
        AppearanceReading reading;
        if (appearance != nullptr) {
          const AppearanceGaze& gaze = ModelFor(*appearance, crop.subject);
          const int eye = crop.ModelEye();
          reading = known_head_pose ? gaze.Read(image, eye, crop.HeadYaw())
                                    : gaze.ReadGivenHeadReading(image, eye, read_head_yaws.at(crop.Photo()));
        }
        const EyePatchFraming framing = known_head_pose ? EyePatchFraming::GivenHeadYaw(crop.HeadYaw())
                                                        : EyePatchFraming::ReadHeadYaw(reading);
        const FitResult result = fitter.FitEyePatchAt(image, crop.ModelEye(), 0, 0, framing, reading);
        ColumbiaFit& fit = fits[i];
        fit.appearance = reading;
        fit.crop = crop;
        fit.seconds = timer.Seconds();
        fit.energy = result.terms.total();
        const Eigen::Vector2d head_label = crop.Label(GazeFrame::kHead);
        fit.in_head = Read(result.phi.gaze_pitch(), EyeRegionModel::EyeYaw(result.phi, crop.ModelEye()), head_label);
        const EyeGaze eye_gaze = EyeGazes(result.phi)[crop.ModelEye()];
        const Eigen::Vector2d angles = GazeAngles(eye_gaze.gaze) - GazeAngles(-eye_gaze.centre);
        fit.in_camera = Read(-RadToDeg(angles.y()), RadToDeg(angles.x()), crop.Label(GazeFrame::kCamera));
        fit.head_pitch = result.phi.rotation_deg().x();
        fit.head_yaw = result.phi.rotation_deg().y();
        for (const FitIteration& iterate : result.history) {
          fit.energy_by_iteration.push_back(iterate.terms.image);
          fit.gaze_error_by_iteration.push_back(GazeAngleBetween(iterate.phi.gaze_pitch(),
                                                                 EyeRegionModel::EyeYaw(iterate.phi, crop.ModelEye()),
                                                                 head_label.x(), head_label.y()));
        }
        const int finished = ++done;
        if (progress) {
          std::lock_guard<std::mutex> lock(progress_mutex);
          progress(finished);
        }
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      if (!error) error = std::current_exception();
      next = static_cast<int>(crops.size());
    }
  };
  std::vector<std::thread> workers;
  for (int t = 1; t < std::max(1, threads); ++t) workers.emplace_back(work);
  work();
  for (std::thread& worker : workers) worker.join();
  if (error) std::rethrow_exception(error);
  ThrowIfInterrupted();
  return fits;
}

}  // namespace gazedirector
