#include "gazedirector/util/gram_matrix.h"

#include <algorithm>
#include <cstring>

namespace gazedirector {
namespace {

// Eight floats in one vector register where the target has them (GCC and
// Clang lower the arithmetic to narrower registers elsewhere).
using Float8 = float __attribute__((vector_size(32)));
constexpr int kLanes = 8;
constexpr int kTile = 3;  // 9 accumulators and 6 loaded vectors fit AVX2's 16 registers

Float8 Load(const float* p) {
  Float8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// The tile of columns [a0, a0 + kTile) x [b0, b0 + kTile); indices past the
// last column repeat it, and only the lower triangle's entries are added.
void AddTile(const std::vector<const float*>& columns, int a0, int b0, Eigen::Index rows, Eigen::MatrixXd& sums) {
  const int n = static_cast<int>(columns.size());
  const float* a[kTile];
  const float* b[kTile];
  for (int k = 0; k < kTile; ++k) {
    a[k] = columns[std::min(a0 + k, n - 1)];
    b[k] = columns[std::min(b0 + k, n - 1)];
  }
  Float8 products[kTile][kTile] = {};
  Eigen::Index i = 0;
  for (; i + kLanes <= rows; i += kLanes) {
    Float8 x[kTile], y[kTile];
    for (int k = 0; k < kTile; ++k) x[k] = Load(a[k] + i), y[k] = Load(b[k] + i);
    for (int p = 0; p < kTile; ++p) {
      for (int q = 0; q < kTile; ++q) products[p][q] += x[p] * y[q];
    }
  }
  for (int p = 0; p < kTile; ++p) {
    for (int q = 0; q < kTile; ++q) {
      if (a0 + p >= n || b0 + q > a0 + p) continue;
      double sum = 0;
      for (int lane = 0; lane < kLanes; ++lane) sum += products[p][q][lane];
      for (Eigen::Index t = i; t < rows; ++t) sum += a[p][t] * b[q][t];
      sums(a0 + p, b0 + q) += sum;
    }
  }
}

}  // namespace

void AddGramLowerTriangle(const std::vector<const float*>& columns, Eigen::Index rows, Eigen::MatrixXd& sums) {
  const int n = static_cast<int>(columns.size());
  for (int a0 = 0; a0 < n; a0 += kTile) {
    for (int b0 = 0; b0 <= a0; b0 += kTile) AddTile(columns, a0, b0, rows, sums);
  }
}

}  // namespace gazedirector
