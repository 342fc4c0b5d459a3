#pragma once
// The finite-strain machinery every isotropic law in logarithmic strain shares (Hencky,
// and the elasto-plastic laws by the exponential map, Simo 1992; AMPLE's detMPs.m):
//   the elastic predictor   b_e,trial = dF exp(2 eps_e,n) dF^T = sum_a l_a n_a (x) n_a,
//                           eps_trial,a = 1/2 ln l_a
//   the consistent tangent  of tau(b_e,trial) = sum_a tau_a n_a (x) n_a for any law whose
//                           principal Kirchhoff stresses tau_a depend on the principal trial
//                           strains: with D_ab = d tau_a / d eps_trial,b (the algorithmic
//                           tangent in principal space) and c_ab = (tau_a - tau_b)/(l_a - l_b),
//   A = iso I(x)I + sum_ab (D_ab - tau_a d_ab) P_aa P_bb^T
//     + sum_{a<b} [c_ab (l_b P_ab P_ab^T + l_a P_ba P_ba^T) + e_ab (P_ab P_ba^T + P_ba P_ab^T)],
//   e_ab = c_ab l_a - tau_a, P_ab = n_a (x) n_b; A_ijkl = d tau_ij / d g_kl - tau_il d_jk
//   for dF -> (I + g) dF. `iso` is an isotropic part of D_ab kept apart so that it is
//   added exactly (Hencky: lambda); D then holds the rest.
#include <Eigen/Core>
#include <cmath>

#include "gradmpm/materials/Material.hpp"

namespace gradmpm {

/// The eigen-decomposition of the trial elastic left Cauchy-Green tensor.
struct ElasticTrial {
  Eigen::Vector3d stretch2;  ///< l_a, principal values of b_e,trial
  Mat3 directions;           ///< n_a (columns)
  /// eps_trial,a = 1/2 ln l_a. Scalar std::log on purpose: Eigen's vectorised log rounds
  /// differently, and the answers of the elastic examples are kept to the last bit.
  Eigen::Vector3d log_strain() const {
    return {0.5 * std::log(stretch2[0]), 0.5 * std::log(stretch2[1]), 0.5 * std::log(stretch2[2])};
  }
};

/// The eigen-decomposition of a symmetric tensor (its lower triangle is read): values
/// ascending, unit vectors in the columns, as Eigen's SelfAdjointEigenSolver. A tensor not
/// coupled to the third axis (m(2,0) = m(2,1) = 0: every plane-strain and uniaxial-strain
/// state) is decomposed in closed form, which keeps those zeros exact; at 1e5 dof in 2D
/// the two decompositions per point were a third of the internal-force loop.
void symmetric_eigen(const Mat3& m, Eigen::Vector3d& values, Mat3& vectors);

/// b_e,trial = dF exp(2 eps_n) dF^T and its eigen-decomposition.
ElasticTrial elastic_trial(const Mat3& dF, const Mat3& eps_n);

/// (ln a - ln b) / (a - b), the divided difference of ln, stable when a ~ b.
double log_divided_difference(double a, double b);

/// The tangent above. `spin` = (c_01, c_02, c_12). Entries with every index below `dim`
/// (dim < 3: plane strain or uniaxial strain need no more; the others are zero).
void spectral_tangent(const ElasticTrial& trial, const Eigen::Vector3d& tau, double iso, const Mat3& D,
                      const Eigen::Vector3d& spin, int dim, Mat9& A);

/// tau_a = n_a . t . n_a: the principal values of t in the trial's frame.
Eigen::Vector3d principal_values(const Mat3& t, const ElasticTrial& trial);

/// (c_01, c_02, c_12) = scale * theta_ab, theta the divided difference of ln of the l_a:
/// the spin terms of laws with tau_a - tau_b = scale (ln l_a - ln l_b).
Eigen::Vector3d spin_coefficients(const ElasticTrial& trial, double scale);

/// The first kTrialCacheSize entries of a response cache: the trial l_a, then n_a.
inline constexpr int kTrialCacheSize = 12;
void store_trial(const ElasticTrial& t, MaterialResponse& r);
ElasticTrial load_trial(const MaterialResponse& r);

}  // namespace gradmpm
