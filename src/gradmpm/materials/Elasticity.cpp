#include "gradmpm/materials/Elasticity.hpp"

namespace gradmpm {

Mat9 IsotropicElasticity::tensor() const {
  Mat9 D = Mat9::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l)
          D(3 * i + j, 3 * k + l) = lambda * (i == j) * (k == l) + mu * ((i == k) * (j == l) + (i == l) * (j == k));
  return D;
}

Mat3 contract(const Mat9& D, const Mat3& e) {
  Mat3 s = Mat3::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) s(i, j) += D(3 * i + j, 3 * k + l) * e(k, l);
  return s;
}

}  // namespace gradmpm
