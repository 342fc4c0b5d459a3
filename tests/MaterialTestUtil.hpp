#pragma once
// Shared by the constitutive tests: update() from a full state block, the consistent
// tangent, and its central-difference check along dF -> (I + h E_kl) dF.
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <vector>

#include "gradmpm/materials/Material.hpp"

namespace gradmpm::test {

struct Updated {
  MaterialResponse r;
  std::vector<double> state;  ///< the new state
};

inline Updated respond(const Material& m, const Mat3& dF, const std::vector<double>& state_n) {
  Updated u;
  u.state.resize(state_n.size());
  m.update(dF, state_n.data(), u.state.data(), u.r);
  return u;
}

inline Mat9 tangent_of(const Material& m, const Mat3& dF, const std::vector<double>& state_n, int dim = 3) {
  const MaterialResponse r = respond(m, dF, state_n).r;
  Mat9 A;
  m.tangent(r, dim, A);
  return A;
}

/// d tau_ij / d g_kl - tau_il delta_jk by central differences of step h.
inline Mat9 finite_difference_tangent(const Material& m, const Mat3& dF, const std::vector<double>& state_n, double h) {
  const MaterialResponse r0 = respond(m, dF, state_n).r;
  Mat9 A;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      Mat3 E = Mat3::Zero();
      E(k, l) = h;
      const MaterialResponse rp = respond(m, (Mat3::Identity() + E) * dF, state_n).r;
      const MaterialResponse rm = respond(m, (Mat3::Identity() - E) * dF, state_n).r;
      const Mat3 dtau = (rp.stress - rm.stress) / (2.0 * h);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) A(3 * i + j, 3 * k + l) = dtau(i, j) - r0.stress(i, l) * (j == k);
    }
  return A;
}

/// dF with principal logarithmic strains `eps` in a rotated frame: from eps_n = 0 the
/// trial strains are exactly eps.
inline Mat3 stretch(const Eigen::Vector3d& eps) {
  const Mat3 Q = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitY()))
                     .toRotationMatrix();
  return Q * eps.array().exp().matrix().asDiagonal() * Q.transpose();
}

/// Principal values of a symmetric tensor, largest first.
inline Eigen::Vector3d sorted_principal(const Mat3& tau) {
  Eigen::SelfAdjointEigenSolver<Mat3> e(tau);
  return {e.eigenvalues()[2], e.eigenvalues()[1], e.eigenvalues()[0]};
}

}  // namespace gradmpm::test
