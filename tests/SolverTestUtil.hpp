#pragma once
// Matrices shared by the linear-solver tests.
#include <vector>

#include "gradmpm/core/Types.hpp"

namespace gradmpm::test {

/// The 2D five-point Laplacian on m x m nodes plus a small shift (4 + 1e-3 on the
/// diagonal: SPD, and incomplete Cholesky is not exact on it); `skew` adds a
/// non-symmetric convection term to the couplings along one axis.
inline SparseMatrix laplacian_2d(int m, double skew = 0.0) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const int k = i * m + j;
      t.emplace_back(k, k, 4.0 + 1e-3);
      if (i + 1 < m) {
        t.emplace_back(k, k + m, -1.0 + skew);
        t.emplace_back(k + m, k, -1.0 - skew);
      }
      if (j + 1 < m) {
        t.emplace_back(k, k + 1, -1.0);
        t.emplace_back(k + 1, k, -1.0);
      }
    }
  SparseMatrix A(m * m, m * m);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

}  // namespace gradmpm::test
