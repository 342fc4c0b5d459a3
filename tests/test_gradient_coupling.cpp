// Requirements on the monolithic coupling of implicit-gradient plasticity
// ([regularisation] coupling = "monolithic", mpm/GradientCoupling.hpp, docs/shear-bands.md):
//  C1 the coupled tangent [K_uu, K_uk; K_ku, K_kk] is the derivative of the coupled
//     residual (central differences of the whole step's residual, 1e-5 of its largest
//     entry) in a softening state of a regularised block, with and without F-bar, for von
//     Mises, Drucker-Prager and Mohr-Coulomb: the sensitivities of each law's return and
//     F-bar's cell terms are consistent;
//  C2 the converged monolithic step satisfies the Helmholtz equation of the staggered
//     scheme: kappa_bar at the points is the smoothing of the converged kappa (to 1e-8 of
//     its largest value);
//  C3 on the softening bar (examples/softening_bar_1d.toml) the monolithic run gives the
//     staggered run's answer (forces to 1e-7 of the peak, eps_p to 1e-4 of its largest) in
//     at most half its Newton iterations, and each plastic step in at most 1.5 times the
//     Newton iterations of the same step of the homogeneous (classical) bar;
//  C4 coupling = "monolithic" is refused with [arc_length], [time] and pore pressure.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <random>

#include "MpmTestUtil.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/mpm/GradientCoupling.hpp"
#include "gradmpm/mpm/ImplicitGradient.hpp"
#include "gradmpm/mpm/LoadStep.hpp"
#include "gradmpm/solver/nonlinear/Newton.hpp"

using namespace gradmpm;

namespace {

// A block squeezed by a platen, its corner patch weaker (the law's strength 10 % lower).
const char* kBlock = R"(
[grid]
origin = [-0.25, -0.25]
cell_size = 0.25
cells = [6, 7]
[basis]
type = "gimp"
[materials.soil]
LAW
[materials.weak]
LAW
[[bodies]]
material = "weak"
min = [0.0, 0.0]
max = [0.25, 0.25]
[[bodies]]
material = "soil"
min = [0.25, 0.0]
max = [1.0, 0.25]
[[bodies]]
material = "soil"
min = [0.0, 0.25]
max = [1.0, 1.25]
[[constraints]]
min = [-0.25, -0.25]
max = [1.25, 0.0]
fix = ["y"]
[[constraints]]
min = [0.5, -0.25]
max = [0.5, 0.0]
fix = ["x"]
[[constraints]]
min = [-0.25, 1.25]
max = [1.5, 1.25]
fix = ["y"]
displacement = [0.0, -0.012]
[load_steps]
count = 3
[regularisation]
type = "implicit-gradient"
length_scale = 0.3
[output]
vtk_every = 0
)";

struct CoupledCheck {
  double error = 0.0;  ///< max |T - T_fd| / max |T| over the free rows and columns
  int plastic = 0;     ///< regularised points plastic at the iterate
  int dofs = 0;
};

const std::string kVonMises = "model = \"von-mises\"\nyoung = 1000.0\npoisson = 0.3\nyield_stress = 2.0\nhardening = -30.0";

/// The block with both materials' keys `law` (their differences in `overrides`).
CaseFile block_case(const std::string& law, const std::vector<std::string>& overrides) {
  std::string text = kBlock;
  for (std::size_t at; (at = text.find("LAW")) != std::string::npos;) text.replace(at, 3, law);
  return CaseFile::parse(text, "block.toml", overrides);
}

/// The coupled step of the block's next load step at a random iterate about the start.
CoupledCheck coupled_tangent_check(const std::string& law, const std::vector<std::string>& overrides) {
  CaseFile cf = block_case(law, overrides);
  MpmCase<2> c = read_mpm_case<2>(cf);
  run_quasi_static<2>(c.model, c.newton);  // softened, moved (GIMP stencils of 3x3 nodes)
  detail::LoadStep<2> step(c.model, 1.0, 0.3);
  NonlocalPlasticStrain<2> nonlocal(c.model, step.stencils(), c.newton.linear_solver);
  detail::GradientCouplingStep<2> coupled(step, c.model, nonlocal);
  const int n = coupled.dofs().num_dofs();
  std::vector<bool> free(n, true);
  for (int k : coupled.constrained()) free[k] = false;
  // An iterate that loads the block further: the step's own first Newton correction,
  // with a random perturbation of every unknown.
  Vector x = Vector::Zero(n), r;
  for (std::size_t k = 0; k < coupled.constrained().size(); ++k) x[coupled.constrained()[k]] = coupled.increments()[k];
  coupled.residual(x, r);
  {
    Eigen::MatrixXd T(coupled.tangent(false));
    for (int i = 0; i < n; ++i)
      if (!free[i]) {
        T.row(i).setZero();
        T.col(i).setZero();
        T(i, i) = 1.0;
      }
    Vector rhs = r;  // (the prescribed columns' share)
    Eigen::MatrixXd T0(coupled.tangent(false));
    for (int i = 0; i < n; ++i)
      if (!free[i]) rhs -= -T0.col(i) * x[i];
    for (int i = 0; i < n; ++i)
      if (!free[i]) rhs[i] = 0.0;
    x += T.partialPivLu().solve(rhs);
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < n; ++i)
    if (free[i]) x[i] += (i % 3 == 2 ? 1e-4 : 2e-5) * u(rng);
  coupled.residual(x, r);
  const Eigen::MatrixXd T(coupled.tangent(false));
  CoupledCheck out;
  out.dofs = n;
  const std::vector<double>& trial = step.trial_state();
  for (int p = 0; p < c.model.points.size(); ++p) {
    const int k = nonlocal.kappa_slot(c.model.points.material[p]);
    out.plastic += k >= 0 && trial[p * c.model.points.state_stride + k] > c.model.points.state_of(p)[k];
  }
  double err = 0.0;
  const double h = 1e-7;
  for (int j = 0; j < n; ++j) {
    if (!free[j]) continue;
    Vector xp = x, xm = x, rp, rm;
    xp[j] += h;
    xm[j] -= h;
    coupled.residual(xp, rp);
    coupled.residual(xm, rm);
    const Vector fd = -(rp - rm) / (2 * h);
    for (int i = 0; i < n; ++i)
      if (free[i]) err = std::max(err, std::abs(fd[i] - T(i, j)));
  }
  double scale = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (free[i] && free[j]) scale = std::max(scale, std::abs(T(i, j)));
  out.error = err / scale;
  return out;
}

}  // namespace

TEST(GradientCoupling, TangentIsTheDerivativeOfTheCoupledResidual) {
  const std::string drucker_prager =
      "model = \"drucker-prager\"\nyoung = 1000.0\npoisson = 0.3\ncohesion = 3.0\nfriction_angle = 20.0\n"
      "dilation_angle = 5.0\nhardening = -5.0\nresidual_cohesion = 0.5";
  const std::string mohr_coulomb =
      "model = \"mohr-coulomb\"\nyoung = 1000.0\npoisson = 0.3\ncohesion = 3.0\nfriction_angle = 20.0\n"
      "dilation_angle = 5.0\nhardening = -5.0\nresidual_cohesion = 0.5";
  struct Case {
    const char* name;
    std::string law;
    std::vector<std::string> overrides;
  };
  const std::vector<Case> cases = {
      {"von Mises", kVonMises, {"materials.weak.yield_stress=1.8"}},
      {"von Mises, F-bar", kVonMises, {"materials.weak.yield_stress=1.8", "mpm.fbar=true"}},
      {"Drucker-Prager, F-bar", drucker_prager, {"materials.weak.cohesion=2.7", "mpm.fbar=true"}},
      {"Mohr-Coulomb", mohr_coulomb, {"materials.weak.cohesion=2.7"}},
  };
  for (const Case& k : cases) {
    const CoupledCheck check = coupled_tangent_check(k.law, k.overrides);
    std::cout << k.name << ": " << check.dofs << " unknowns, " << check.plastic
              << " plastic points, max |T - T_fd| / max |T| = " << check.error << "\n";
    EXPECT_GT(check.plastic, 0) << k.name;
    EXPECT_LT(check.error, 1e-5) << k.name;
  }
}

TEST(GradientCoupling, ConvergedStepSatisfiesTheHelmholtzEquation) {
  CaseFile cf = block_case(kVonMises, {"materials.weak.yield_stress=1.8", "load_steps.count=4"});
  MpmCase<2> c = read_mpm_case<2>(cf);
  run_quasi_static<2>(c.model, c.newton);
  // One more load step by the monolithic Newton, then kappa_bar against the smoothing of
  // the converged kappa (the staggered scheme's map G, with the same operator).
  detail::LoadStep<2> step(c.model, 1.25, 0.25);
  NonlocalPlasticStrain<2> nonlocal(c.model, step.stencils(), c.newton.linear_solver);
  detail::GradientCouplingStep<2> coupled(step, c.model, nonlocal);
  NewtonSolver newton;
  newton.start_step();
  NewtonLog log;
  newton.solve(coupled, c.newton, log, nullptr);
  const std::vector<double> converged = step.trial_state();
  std::vector<double> smoothed = converged;
  nonlocal.smooth(converged, smoothed);
  double largest = 0.0, diff = 0.0, kappa = 0.0;
  for (int p : nonlocal.regularised_points()) {
    const std::size_t base = static_cast<std::size_t>(p) * c.model.points.state_stride;
    const int m = c.model.points.material[p];
    const double k_bar = converged[base + nonlocal.nonlocal_slot(m)];
    largest = std::max(largest, std::abs(k_bar));
    diff = std::max(diff, std::abs(k_bar - smoothed[base + nonlocal.nonlocal_slot(m)]));
    kappa = std::max(kappa, converged[base + nonlocal.kappa_slot(m)] - c.model.points.state_of(p)[nonlocal.kappa_slot(m)]);
  }
  std::cout << "Newton iterations " << log.residuals.size() - 1 << ", largest kappa_bar " << largest
            << ", largest kappa increment " << kappa << ", max |kappa_bar - G(kappa)| " << diff << "\n";
  EXPECT_GT(kappa, 0.0) << "the step is plastic";
  EXPECT_LT(diff, 1e-8 * largest);
}
