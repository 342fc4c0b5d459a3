#pragma once
// The six independent components of a symmetric 3x3 tensor, in the one order every
// output and every state block uses: xx, yy, zz, xy, yz, xz.
#include <Eigen/Core>
#include <array>

namespace gradmpm {

struct SymmetricComponent {
  int i, j;          ///< row and column, i <= j
  const char* name;  ///< "xx", "yy", ...
};

inline constexpr std::array<SymmetricComponent, 6> kSymmetricComponents{
    {{0, 0, "xx"}, {1, 1, "yy"}, {2, 2, "zz"}, {0, 1, "xy"}, {1, 2, "yz"}, {0, 2, "xz"}}};

/// Writes the six components of t. The off-diagonal ones are read from the lower
/// triangle, the one Eigen's SelfAdjointEigenSolver reads, so a tensor that is
/// symmetric only to round-off round-trips to what an eigen-solve would have seen.
inline void pack_symmetric(const Eigen::Matrix3d& t, double* out) {
  for (int c = 0; c < 6; ++c) out[c] = t(kSymmetricComponents[c].j, kSymmetricComponents[c].i);
}

inline Eigen::Matrix3d unpack_symmetric(const double* in) {
  Eigen::Matrix3d t;
  for (int c = 0; c < 6; ++c)
    t(kSymmetricComponents[c].i, kSymmetricComponents[c].j) = t(kSymmetricComponents[c].j, kSymmetricComponents[c].i) =
        in[c];
  return t;
}

}  // namespace gradmpm
