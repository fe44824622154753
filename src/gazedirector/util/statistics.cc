#include "gazedirector/util/statistics.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace gazedirector {

double Mean(const std::vector<double>& values) {
  return values.empty() ? 0.0 : std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
}

namespace {

// The q-quantile of sorted, non-empty `values`.
double SortedQuantile(const std::vector<double>& values, double q) {
  const double position = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  const double weight = position - static_cast<double>(below);
  return values[below] * (1 - weight) + values[above] * weight;
}

}  // namespace

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return SortedQuantile(values, q);
}

std::array<double, 3> Quartiles(std::vector<double> values) {
  if (values.empty()) return {0.0, 0.0, 0.0};
  std::sort(values.begin(), values.end());
  return {SortedQuantile(values, 0.25), SortedQuantile(values, 0.5), SortedQuantile(values, 0.75)};
}

double Median(std::vector<double> values) { return Quantile(std::move(values), 0.5); }

}  // namespace gazedirector
