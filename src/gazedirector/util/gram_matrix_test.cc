#include "gazedirector/util/gram_matrix.h"

#include <gtest/gtest.h>

namespace gazedirector {
namespace {

// Against the same sums in double, for column counts around the tile size
// and row ranges (unaligned starts, counts that do not fill the last vector):
// the lower triangle within float rounding, the upper triangle untouched.
TEST(GramMatrixTest, AddsTheLowerTriangleOfEveryPairsDotProduct) {
  for (int n : {1, 2, 3, 4, 7, 20}) {
    const Eigen::MatrixXf x = Eigen::MatrixXf::Random(1003, n);
    for (auto [begin, end] : {std::pair<Eigen::Index, Eigen::Index>{0, 1003}, {5, 12}, {17, 990}, {3, 3}}) {
      std::vector<const float*> columns;
      for (int c = 0; c < n; ++c) columns.push_back(x.col(c).data() + begin);
      Eigen::MatrixXd sums = Eigen::MatrixXd::Constant(n, n, 1.0);
      AddGramLowerTriangle(columns, end - begin, sums);
      const Eigen::MatrixXd rows = x.middleRows(begin, end - begin).cast<double>();
      const Eigen::MatrixXd expected = rows.transpose() * rows;
      for (int a = 0; a < n; ++a) {
        for (int b = 0; b < n; ++b) {
          const double want = b <= a ? 1.0 + expected(a, b) : 1.0;
          EXPECT_NEAR(sums(a, b), want, 1e-5 * (1.0 + std::abs(expected(a, a)))) << n << " columns, " << a << ", " << b;
        }
      }
    }
  }
}

}  // namespace
}  // namespace gazedirector
