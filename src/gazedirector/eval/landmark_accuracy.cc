#include "gazedirector/eval/landmark_accuracy.h"

#include <dlib/data_io/image_dataset_metadata.h>

#include <opencv2/imgproc.hpp>

#include "gazedirector/face/turned_crop.h"
#include "gazedirector/geometry/rotation.h"
#include "gazedirector/io/image_io.h"
#include "gazedirector/util/error.h"
#include "gazedirector/util/statistics.h"

namespace gazedirector {

double LandmarkAccuracy::MeanGivenBox() const { return Mean(given_box_errors); }
double LandmarkAccuracy::MedianGivenBox() const { return Median(given_box_errors); }
double LandmarkAccuracy::MeanPipeline() const { return Mean(pipeline_errors); }
double LandmarkAccuracy::MedianPipeline() const { return Median(pipeline_errors); }

double NormalisedLandmarkError(const Landmarks68& predicted, const Landmarks68& truth) {
  double sum = 0;
  for (int i = 0; i < kNumLandmarks; ++i) sum += (predicted[i] - truth[i]).norm();
  return sum / kNumLandmarks / (truth[36] - truth[45]).norm();
}

LandmarkAccuracy EvaluateLandmarks(const std::filesystem::path& xml, FaceTracker& tracker,
                                   const LandmarkDetector& landmark_detector, double turn_deg) {
  dlib::image_dataset_metadata::dataset dataset;
  try {
    dlib::image_dataset_metadata::load_image_dataset_metadata(dataset, xml.string());
  } catch (const std::exception& e) {
    Fail(ExitCode::kBadInput, "cannot read {}: {}", xml.string(), e.what());
  }
  LandmarkAccuracy accuracy;
  const double roll = DegToRad(turn_deg);
  for (const auto& entry : dataset.images) {
    cv::Mat image = ReadImage(xml.parent_path() / entry.filename);
    // Content upright in the photo stands at `roll` in a crop turned by -roll.
    const TurnedCrop turned = TurnedCrop::WholeImage(image.size(), -roll, 1.0);
    if (roll != 0) image = turned.Cut(image, cv::BORDER_CONSTANT);
    auto turn = [&](const Eigen::Vector2d& p) { return roll != 0 ? turned.ToCrop(p) : p; };
    cv::Mat gray;
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
    const std::vector<Face> found = tracker.DetectFaces(image, Camera::Default(image.cols, image.rows));
    for (const auto& box : entry.boxes) {
      if (box.parts.size() != kNumLandmarks) continue;
      Landmarks68 truth;
      for (const auto& [name, point] : box.parts) truth[std::stoi(name)] = turn(Eigen::Vector2d(point.x(), point.y()));
      ++accuracy.faces;
      const cv::Rect2d rect(box.rect.left(), box.rect.top(), box.rect.width(), box.rect.height());
      const cv::Rect2d marked = roll != 0 ? turned.BoxInCrop(rect) : rect;
      accuracy.given_box_errors.push_back(NormalisedLandmarkError(landmark_detector.Detect(gray, marked, roll), truth));
      // The detected face whose landmarks lie closest to the marked ones.
      double best = 1e9;
      for (const Face& face : found) best = std::min(best, NormalisedLandmarkError(face.landmarks, truth));
      if (best < 0.5) {
        ++accuracy.detected;
        accuracy.pipeline_errors.push_back(best);
      }
    }
  }
  return accuracy;
}

}  // namespace gazedirector
