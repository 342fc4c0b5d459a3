// Requirements on the constitutive updates (materials/Material.hpp):
//  R1 the Hencky tangent is the derivative of the linearised internal virtual work:
//     A_ijkl = d tau_ij / d g_kl - tau_il delta_jk, with dF -> (I + g) dF, checked
//     against central finite differences at a general 3D state (rotated, sheared,
//     compressed) and at states with two or three equal principal stretches;
//  R2 that tangent has the major symmetry A_ijkl = A_klij (hyperelasticity) that lets
//     the global stiffness be factorised by Cholesky;
//  R3 Hencky at a vanishing strain is linear elasticity: tau = D : eps + O(eps^2) and
//     the tangent tends to D;
//  R4 the spectral form of that tangent (nine rank-one terms) equals the textbook dense
//     form 1/2 D : L : B - tau_il delta_jk to round-off;
//  R5 the plane (dim = 2) and uniaxial (dim = 1) tangents are the in-plane blocks of
//     the full one;
//  R6 the Hencky stress is D : (1/2 ln b_e) exactly, b_e = dF exp(2 eps_n) dF^T, and
//     the returned strain is the history the next step starts from;
//  R7 linear elasticity accumulates eps_n + sym(dF - I), returns D : eps and the tangent D;
//  R8 both keep their history as one declared state variable, the symmetric tensor
//     elastic_strain, which their elastic_strain() reads back.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "MaterialTestUtil.hpp"
#include "gradmpm/core/SymmetricTensor.hpp"
#include "gradmpm/materials/Hencky.hpp"
#include "gradmpm/materials/LinearElastic.hpp"

using namespace gradmpm;

namespace {

/// update() from an elastic-strain history: the response and the new strain.
struct Updated {
  MaterialResponse r;
  Mat3 strain;
};
std::vector<double> history(const Mat3& strain_n) {
  std::vector<double> s(6);
  pack_symmetric(strain_n, s.data());
  return s;
}
Updated respond(const Material& m, const Mat3& dF, const Mat3& strain_n) {
  const test::Updated u = test::respond(m, dF, history(strain_n));
  return {u.r, m.elastic_strain(u.state.data())};
}

Mat9 isotropic_elasticity(double young, double poisson) { return IsotropicElasticity(young, poisson).tensor(); }

Mat9 tangent_of(const Material& m, const Mat3& dF, const Mat3& strain_n) {
  return test::tangent_of(m, dF, history(strain_n));
}
Mat9 finite_difference_tangent(const Material& m, const Mat3& dF, const Mat3& strain_n, double h) {
  return test::finite_difference_tangent(m, dF, history(strain_n), h);
}

Mat3 rotation(double a, double b, double c) {
  return (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(c, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

const Hencky hencky(1000.0, 0.3, 1.0);

/// The textbook form A = 1/2 D : L : B - tau_il delta_jk, with L = d ln b / d b (the
/// Daleckii-Krein sum) and B_pqkl = delta_pk b_lq + delta_qk b_pl, as dense 9x9 products.
Mat9 dense_hencky_tangent(const MaterialResponse& r, double young, double poisson) {
  const auto at = [](int i, int j) { return 3 * i + j; };
  const Eigen::Vector3d lam = Eigen::Map<const Eigen::Vector3d>(r.cache.data());  // Hencky's tangent cache
  const Mat3 n = Eigen::Map<const Mat3>(r.cache.data() + 3);
  const Mat3 be = n * lam.asDiagonal() * n.transpose();
  Mat3 theta;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      theta(a, b) = std::abs(lam[a] - lam[b]) < 1e-12 * lam[a]
                        ? 1.0 / lam[a]
                        : (std::log(lam[a]) - std::log(lam[b])) / (lam[a] - lam[b]);
  Mat9 L = Mat9::Zero();
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      Eigen::Matrix<double, 9, 1> m;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m[at(i, j)] = n(i, a) * n(j, b);
      L += theta(a, b) * m * m.transpose();
    }
  Mat9 B = Mat9::Zero(), T = Mat9::Zero();
  for (int p = 0; p < 3; ++p)
    for (int q = 0; q < 3; ++q)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) {
          B(at(p, q), at(k, l)) = (p == k) * be(l, q) + (q == k) * be(p, l);
          T(at(p, q), at(k, l)) = r.stress(p, l) * (q == k);
        }
  return 0.5 * isotropic_elasticity(young, poisson) * L * B - T;
}

}  // namespace

TEST(Hencky, TangentMatchesFiniteDifferencesAtAGeneralState) {
  Mat3 U;
  U << 0.7, 0.1, 0.05, 0.1, 1.2, -0.08, 0.05, -0.08, 0.9;
  const Mat3 dF = rotation(0.3, -0.2, 0.5) * U;
  Mat3 eps_n;
  eps_n << -0.1, 0.03, 0.0, 0.03, 0.05, 0.02, 0.0, 0.02, -0.04;
  const Mat9 A = tangent_of(hencky, dF, eps_n);
  const Mat9 Afd = finite_difference_tangent(hencky, dF, eps_n, 1e-6);
  const double err = (A - Afd).cwiseAbs().maxCoeff() / A.cwiseAbs().maxCoeff();
  std::printf("general state: max |A - A_fd| / max |A| = %.2e\n", err);
  EXPECT_LT(err, 1e-7);
}

TEST(Hencky, TangentMatchesFiniteDifferencesWithEqualPrincipalStretches) {
  // Two equal stretches (axisymmetric) and three (pure dilatation), rotated: the
  // divided differences of ln take their limits there.
  const Mat3 Q = rotation(-0.4, 0.7, 0.1);
  for (const Eigen::Vector3d& s : {Eigen::Vector3d(0.8, 0.8, 1.1), Eigen::Vector3d(0.9, 0.9, 0.9)}) {
    const Mat3 dF = Q * s.asDiagonal() * Q.transpose();
    const Mat9 A = tangent_of(hencky, dF, Mat3::Zero());
    const Mat9 Afd = finite_difference_tangent(hencky, dF, Mat3::Zero(), 1e-6);
    const double err = (A - Afd).cwiseAbs().maxCoeff() / A.cwiseAbs().maxCoeff();
    std::printf("stretches (%.1f, %.1f, %.1f): max |A - A_fd| / max |A| = %.2e\n", s[0], s[1], s[2], err);
    EXPECT_LT(err, 1e-7);
  }
}

TEST(Hencky, TangentHasMajorSymmetry) {
  Mat3 dF;
  dF << 0.8, 0.3, -0.1, 0.05, 1.1, 0.2, 0.1, -0.2, 0.95;
  Mat3 eps_n;
  eps_n << 0.02, -0.01, 0.0, -0.01, -0.05, 0.01, 0.0, 0.01, 0.03;
  const Mat9 A = tangent_of(hencky, dF, eps_n);
  const double asym = (A - A.transpose()).cwiseAbs().maxCoeff() / A.cwiseAbs().maxCoeff();
  std::printf("max |A - A^T| / max |A| = %.2e\n", asym);
  EXPECT_LT(asym, 1e-13);
}

TEST(Hencky, SpectralTangentEqualsTheDenseForm) {
  Mat3 dF;
  dF << 0.75, 0.2, -0.1, 0.1, 1.25, 0.15, -0.05, 0.1, 0.9;
  Mat3 eps_n;
  eps_n << 0.05, -0.02, 0.01, -0.02, -0.1, 0.0, 0.01, 0.0, 0.02;
  const MaterialResponse r = respond(hencky, dF, eps_n).r;
  Mat9 A;
  hencky.tangent(r, 3, A);
  const Mat9 Ad = dense_hencky_tangent(r, 1000.0, 0.3);
  const double err = (A - Ad).cwiseAbs().maxCoeff() / Ad.cwiseAbs().maxCoeff();
  std::printf("spectral vs dense tangent: %.2e\n", err);
  EXPECT_LT(err, 1e-13);
}

TEST(Hencky, PlaneAndUniaxialTangentsAreBlocksOfTheFullOne) {
  Mat3 dF = Mat3::Identity();
  dF.topLeftCorner<2, 2>() << 0.8, 0.25, -0.1, 1.15;  // plane strain kinematics
  Mat3 eps_n = Mat3::Zero();
  eps_n.topLeftCorner<2, 2>() << 0.03, -0.02, -0.02, -0.06;
  const MaterialResponse r = respond(hencky, dF, eps_n).r;
  Mat9 full;
  hencky.tangent(r, 3, full);
  for (int dim : {1, 2}) {
    Mat9 A;
    hencky.tangent(r, dim, A);
    double err = 0.0;
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j)
        for (int k = 0; k < dim; ++k)
          for (int l = 0; l < dim; ++l)
            err = std::max(err, std::abs(A(3 * i + j, 3 * k + l) - full(3 * i + j, 3 * k + l)));
    EXPECT_LT(err, 1e-13 * full.cwiseAbs().maxCoeff()) << "dim " << dim;
  }
}

TEST(Hencky, SmallStrainLimitIsLinearElasticity) {
  const Mat9 D = isotropic_elasticity(1000.0, 0.3);
  Mat3 g;
  g << 0.3, -0.2, 0.1, 0.4, -0.1, 0.25, -0.15, 0.05, 0.2;
  const Mat3 eps = 0.5 * (g + g.transpose());
  for (double t : {1e-3, 1e-4, 1e-5}) {
    const MaterialResponse r = respond(hencky, Mat3::Identity() + t * g, Mat3::Zero()).r;
    const Mat3 linear = hencky.elasticity().stress(t * eps);
    const double rel = (r.stress - linear).norm() / linear.norm();
    std::printf("strain scale %.0e: |tau - D:eps| / |D:eps| = %.2e\n", t, rel);
    EXPECT_LT(rel, 5.0 * t);  // O(eps^2) / O(eps)
  }
  const Mat9 A0 = tangent_of(hencky, Mat3::Identity(), Mat3::Zero());
  EXPECT_LT((A0 - D).cwiseAbs().maxCoeff(), 1e-12 * D.cwiseAbs().maxCoeff());
}

TEST(Hencky, StressIsElasticityOfTheLogarithmicStrain) {
  Mat3 dF;
  dF << 1.3, 0.2, 0.0, -0.1, 0.7, 0.1, 0.05, 0.0, 1.05;
  Mat3 eps_n;
  eps_n << 0.1, 0.02, 0.0, 0.02, -0.2, 0.0, 0.0, 0.0, 0.05;
  const Updated u = respond(hencky, dF, eps_n);
  // Reference: b_e and its logarithm through a general eigen-decomposition.
  Eigen::SelfAdjointEigenSolver<Mat3> en(eps_n);
  const Mat3 be_n =
      en.eigenvectors() * (2.0 * en.eigenvalues()).array().exp().matrix().asDiagonal() * en.eigenvectors().transpose();
  Eigen::SelfAdjointEigenSolver<Mat3> eb(dF * be_n * dF.transpose());
  const Mat3 eps =
      eb.eigenvectors() * (0.5 * eb.eigenvalues().array().log()).matrix().asDiagonal() * eb.eigenvectors().transpose();
  EXPECT_LT((u.strain - eps).norm(), 1e-14);
  EXPECT_LT((u.r.stress - hencky.elasticity().stress(eps)).norm(), 1e-11);
}

TEST(LinearElastic, StressAndTangentAreIsotropicElasticity) {
  const LinearElastic lin(200.0, 0.25, 1.0);
  const Mat9 D = isotropic_elasticity(200.0, 0.25);
  Mat3 g;
  g << 0.01, 0.002, 0.0, -0.004, -0.003, 0.001, 0.0, 0.002, 0.005;
  Mat3 eps_n = Mat3::Zero();
  eps_n(0, 1) = eps_n(1, 0) = 0.001;
  const Updated u = respond(lin, Mat3::Identity() + g, eps_n);
  const Mat3 eps = eps_n + 0.5 * (g + g.transpose());
  EXPECT_LT((u.strain - eps).norm(), 1e-15);
  EXPECT_LT((u.r.stress - lin.elasticity().stress(eps)).norm(), 1e-13);
  Mat9 A;
  lin.tangent(u.r, 3, A);
  EXPECT_EQ(A, D);
}

TEST(Materials, ElasticLawsDeclareTheirStateAsTheElasticStrainTensor) {
  const LinearElastic lin(200.0, 0.25, 1.0);
  for (const Material* m : {static_cast<const Material*>(&hencky), static_cast<const Material*>(&lin)}) {
    ASSERT_EQ(m->state_variables().size(), 1u) << m->model();
    EXPECT_EQ(m->state_variables()[0].name, "elastic_strain");
    EXPECT_EQ(m->state_variables()[0].kind, StateVariable::Kind::SymmetricTensor);
    EXPECT_EQ(m->state_size(), 6);
    double s[6];
    m->initial_state(s);
    EXPECT_EQ(m->elastic_strain(s), Mat3::Zero());
    Mat3 e;
    e << 0.1, 0.02, -0.03, 0.02, -0.2, 0.04, -0.03, 0.04, 0.05;
    pack_symmetric(e, s);
    EXPECT_EQ(m->elastic_strain(s), e) << m->model();
  }
}
