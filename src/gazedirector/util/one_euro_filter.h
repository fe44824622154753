#pragma once

#include <cmath>

namespace gazedirector {

// The 1-euro filter (Casiez et al., CHI 2012): a low-pass filter whose cutoff
// rises with speed, so that still signals lose their jitter while fast
// movements pass with little lag.
class OneEuroFilter {
 public:
  OneEuroFilter(double min_cutoff_hz, double beta, double derivative_cutoff_hz = 1.0)
      : min_cutoff_(min_cutoff_hz), beta_(beta), derivative_cutoff_(derivative_cutoff_hz) {}

  // `speed_unit` rescales the speed that raises the cutoff (for example the
  // size of a face in pixels, so that beta means the same near and far).
  double Filter(double value, double dt_s, double speed_unit = 1.0) {
    if (!initialized_ || dt_s <= 0) {
      initialized_ = true;
      value_ = value;
      derivative_ = 0;
      return value;
    }
    const double raw_derivative = (value - value_) / dt_s;
    derivative_ += Alpha(derivative_cutoff_, dt_s) * (raw_derivative - derivative_);
    const double cutoff = min_cutoff_ + beta_ * std::abs(derivative_) / speed_unit;
    value_ += Alpha(cutoff, dt_s) * (value - value_);
    return value_;
  }

  void Reset() { initialized_ = false; }
  double value() const { return value_; }

 private:
  static double Alpha(double cutoff_hz, double dt_s) {
    const double tau = 1.0 / (2.0 * 3.14159265358979323846 * cutoff_hz);
    return 1.0 / (1.0 + tau / dt_s);
  }

  double min_cutoff_;
  double beta_;
  double derivative_cutoff_;
  bool initialized_ = false;
  double value_ = 0;
  double derivative_ = 0;
};

}  // namespace gazedirector
