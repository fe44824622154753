#include "gazedirector/fit/fitting_problem.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "gazedirector/fit/fitter.h"
#include "gazedirector/io/image_io.h"
#include "tests/test_data.h"

namespace gazedirector {
namespace {

using testing::SharedModel;

// A real Columbia crop of the image-left eye (the model's right eye), set up
// as an eye-patch fit sets it up, at the crop's own resolution.
struct CropProblem {
  CropProblem() {
    const cv::Mat crop = ReadImage(testing::DataPath("columbia-eyes/0003_2m_0P_0V_10H_L.jpg"));
    cv::Mat rgb;
    cv::cvtColor(crop, rgb, cv::COLOR_BGR2RGB);
    rgb.convertTo(rgb, CV_32FC3, 1.0 / 255.0);
    const Camera camera = Fitter::EyePatchCamera(crop.size());
    const LandmarkModel framing = LandmarkModel(*SharedModel()).EyeCentre(kRightEye);
    problem = std::make_unique<FittingProblem>(SharedModel(), rgb, camera, framing,
                                               std::vector<Eigen::Vector2d>{{camera.cx, camera.cy}},
                                               std::vector<double>{1.0}, EnergyWeights{}, std::array<bool, 2>{false, true});
    Fitter fitter(SharedModel());
    phi = fitter.EyePatchStart(crop.size(), kRightEye);
    // A gaze other than the photo's, with the lids left behind: every term of
    // the energy is then at work.
    phi.gaze_pitch() = 5;
    phi.gaze_yaw() = 8;
  }

  // Evaluates at Φ, makes that render's footprint and a 2 px margin the
  // domain (as each Gauss-Newton step does), and evaluates again for the
  // residuals.
  struct OnItsDomain {
    EnergyTerms first;  // before the domain was set
    EnergyTerms terms;
    Eigen::VectorXf residuals;
  };
  OnItsDomain EvaluateOnItsDomain(EvaluationWorkspace& work) const {
    OnItsDomain result;
    result.first = problem->Evaluate(phi, work, nullptr);
    problem->SetDomain(work.buffers, 2);
    result.terms = problem->Evaluate(phi, work, &result.residuals);
    return result;
  }

  std::unique_ptr<FittingProblem> problem;
  Parameters phi;
};

// Gauss-Newton minimises the sum of squared residuals, so that sum must be
// the energy: at the Φ whose render set the domain, the domain holds every
// rendered pixel, and the image residuals carry the truncation, the area
// normalisation and the eyeball weight.
TEST(FittingProblemTest, ResidualsSquareToTheEnergy) {
  for (double eyeball_weight : {1.0, 3.0}) {
    CropProblem crop;
    crop.problem->weights().eyeball_pixels = eyeball_weight;
    EvaluationWorkspace work(SharedModel());
    const CropProblem::OnItsDomain evaluated = crop.EvaluateOnItsDomain(work);
    const EnergyTerms& terms = evaluated.first;
    const Eigen::VectorXf& residuals = evaluated.residuals;
    ASSERT_GT(terms.foreground, 1000);
    EXPECT_EQ(evaluated.terms.total(), terms.total());
    ASSERT_EQ(residuals.size(), crop.problem->num_residuals());
    EXPECT_NEAR(residuals.cast<double>().squaredNorm(), terms.total(), 1e-5 * terms.total()) << "eyeball weight " << eyeball_weight;
    const double image = residuals.head(crop.problem->num_image_residuals()).cast<double>().squaredNorm();
    EXPECT_NEAR(image, terms.image, 1e-5 * terms.image);
    EXPECT_GT(terms.landmarks, 0);
    EXPECT_GT(terms.pose, 0);
  }
}

// The appearance gaze prior adds λ_app,p (θ_p - θ_app,p)² + λ_app,y (θ_y -
// θ_app,y)² to the pose term, in the energy and in its last two residuals
// alike; without a reading it adds nothing.
TEST(FittingProblemTest, TheAppearanceGazePullsTowardItsReading) {
  CropProblem crop;
  crop.phi.gaze_yaw() = 4;
  EvaluationWorkspace work(SharedModel());
  const CropProblem::OnItsDomain without = crop.EvaluateOnItsDomain(work);
  const Eigen::Index last = without.residuals.size() - 1;
  EXPECT_EQ(without.residuals[last - 1], 0.0f);
  EXPECT_EQ(without.residuals[last], 0.0f);
  const AppearanceReading reading{-7, 9};
  crop.problem->set_appearance(reading);
  const CropProblem::OnItsDomain with = crop.EvaluateOnItsDomain(work);
  const EnergyWeights& weights = crop.problem->weights();
  ASSERT_GT(weights.appearance_pitch, 0);
  ASSERT_GT(weights.appearance_yaw, 0);
  const double pitch_miss = crop.phi.gaze_pitch() - reading.pitch, yaw_miss = crop.phi.gaze_yaw() - reading.yaw;
  EXPECT_NEAR(with.terms.pose - without.terms.pose,
              weights.appearance_pitch * pitch_miss * pitch_miss + weights.appearance_yaw * yaw_miss * yaw_miss, 1e-12);
  EXPECT_EQ(with.terms.image, without.terms.image);
  EXPECT_NEAR(with.residuals[last - 1], std::sqrt(weights.appearance_pitch) * pitch_miss, 1e-6);
  EXPECT_NEAR(with.residuals[last], std::sqrt(weights.appearance_yaw) * yaw_miss, 1e-6);
  EXPECT_NEAR(with.residuals.cast<double>().squaredNorm(), with.terms.total(), 1e-5 * with.terms.total());

  // Read from a turned head, the yaw is pulled harder by the turned factor.
  crop.problem->weights().appearance_turned_factor = 10;
  AppearanceReading turned = reading;
  turned.frontal = 0;
  crop.problem->set_appearance(turned);
  const CropProblem::OnItsDomain with_turned = crop.EvaluateOnItsDomain(work);
  EXPECT_NEAR(with_turned.residuals[last], std::sqrt(10 * weights.appearance_yaw) * yaw_miss, 1e-6);
  EXPECT_NEAR(with_turned.terms.pose - with.terms.pose, 9 * weights.appearance_yaw * yaw_miss * yaw_miss, 1e-12);
  // Half frontal is a quarter turned.
  EXPECT_NEAR(weights.AppearanceYaw(0.5), weights.appearance_yaw * (0.75 + 0.25 * 10), 1e-15);
}

// No pixel counts more than the truncation T (times the eyeball weight), and
// some do reach it: the misplaced iris, the photo's highlights and lashes.
TEST(FittingProblemTest, TheTruncationCapsEveryPixel) {
  CropProblem crop;
  const double eyeball_weight = 2.0;
  crop.problem->weights().eyeball_pixels = eyeball_weight;
  EvaluationWorkspace work(SharedModel());
  const CropProblem::OnItsDomain evaluated = crop.EvaluateOnItsDomain(work);
  const EnergyTerms& terms = evaluated.first;
  const Eigen::VectorXf& residuals = evaluated.residuals;
  const double cap = crop.problem->weights().truncation / terms.foreground;
  int capped = 0;
  for (int d = 0; d < static_cast<int>(crop.problem->domain().size()); ++d) {
    const double squared = residuals.segment<3>(3 * d).cast<double>().squaredNorm();
    EXPECT_LE(squared, eyeball_weight * cap * (1 + 1e-5)) << "pixel " << crop.problem->domain()[d];
    if (squared >= cap * (1 - 1e-5)) ++capped;
  }
  EXPECT_GT(capped, 0);
}

// The domain is the render's footprint grown by the margin, in raster order.
TEST(FittingProblemTest, TheDomainHoldsTheRenderAndItsMargin) {
  CropProblem crop;
  EvaluationWorkspace work(SharedModel());
  crop.problem->Evaluate(crop.phi, work, nullptr);
  crop.problem->SetDomain(work.buffers, 0);
  EXPECT_EQ(crop.problem->domain(), work.buffers.foreground);
  crop.problem->SetDomain(work.buffers, 2);
  const std::vector<int>& domain = crop.problem->domain();
  EXPECT_TRUE(std::is_sorted(domain.begin(), domain.end()));
  EXPECT_TRUE(std::includes(domain.begin(), domain.end(), work.buffers.foreground.begin(), work.buffers.foreground.end()));
  EXPECT_GT(domain.size(), work.buffers.foreground.size());
}

}  // namespace
}  // namespace gazedirector
