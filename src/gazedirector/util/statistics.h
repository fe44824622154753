#pragma once

#include <array>
#include <vector>

namespace gazedirector {

double Mean(const std::vector<double>& values);
// The median (mean of the middle two for even counts); 0 for no values.
double Median(std::vector<double> values);
// The q-quantile (0..1) with linear interpolation.
double Quantile(std::vector<double> values, double q);
// The 0.25, 0.5 and 0.75 quantiles, as Quantile gives them, from one sort.
std::array<double, 3> Quartiles(std::vector<double> values);

}  // namespace gazedirector
