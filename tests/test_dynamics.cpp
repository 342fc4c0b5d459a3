// Requirements of implicit MPM dynamics ([time]; mpm/Dynamics.hpp, docs/dynamics.md):
//   D1 a block released under gravity falls as x0 - g t^2 / 2 with v = -g t, to round-off,
//      with Newmark and generalised-alpha, lumped and consistent mass; a block thrown
//      ([[bodies]] velocity) flies as x0 + v0 t + g t^2 / 2;
//   D2 the axial vibration of a fixed-free elastic bar (1D, and as a 2D strip): with the
//      consistent mass its period is the discrete closed form's (the linear basis's
//      dispersion, the trapezoidal rule's period elongation) to 1e-6, and the continuum's
//      4 L / c within 0.5 % at 32 cells per wavelength; with the lumped mass (whose point-grid transfer smooths the
//      velocity) within 0.5 % at 64, converging at second order (figures at 16, 32, 64);
//   D3 with the consistent mass the trapezoidal rule conserves kinetic + elastic energy to
//      1e-6 per period over 20 periods (Love & Sulsky 2006: the consistent mass makes the
//      point-grid transfer lossless);
//   D4 generalised-alpha damps a mode far above 1 / dt by rho_inf per step, and the
//      trapezoidal rule not at all (Chung & Hulbert 1993);
//   D5 an elastic column under gravity switched on at t = 0, with Rayleigh damping, comes
//      to rest (stop_at_rest = 1e-8: the kinetic energy 1e-8 of its peak, the inertia and
//      damping forces 1e-4 of the forces in balance) and its base then carries its weight
//      to 1e-3 (the guard of the long test of the vertical cut's
//      collapse to rest, tests/test_collapse_dynamic.cpp);
//   D6 a slender cantilever (L / t = 20, plane strain, nu = 0) set moving by a uniform
//      transverse velocity vibrates at the Euler-Bernoulli first bending frequency
//      1.8751^2 sqrt(E I / (rho A L^4)) within 2 % (4 and 8 cells through the thickness,
//      consistent and lumped mass; the period from the free end's zero crossings over
//      five periods).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <functional>
#include <iostream>
#include <numbers>

#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/materials/LinearElastic.hpp"
#include "gradmpm/mpm/QuasiStatic.hpp"
#include "gradmpm/points/Generate.hpp"

using namespace gradmpm;

namespace {

constexpr double kPi = std::numbers::pi;

/// A fixed-free bar on [0, L = 1] (fixed at x = 0) of `n` cells with 2 points per cell,
/// one empty cell beyond its free end; E = 100, rho = 1: c = 10.
Model<1> fixed_free_bar(int n, double young = 100.0) {
  const double h = 1.0 / n;
  Model<1> m(Grid<1>(Vec<1>(0.0), Vec<1>(h), {n + 1}));
  m.materials = {std::make_shared<LinearElastic>(young, 0.0, 1.0)};
  add_regular_points<1>(m.grid, {0}, {n}, 2, [](const Vec<1>&) { return true; }, 0, 1.0, m.points);
  m.constraints = {{0, 0, 0.0}};
  return m;
}

/// Gives the points the velocity that interpolates v(x) at the grid nodes (so that the
/// grid's projection of it is v at the nodes, with the consistent mass).
void interpolated_velocity(Model<1>& m, const std::function<double(double)>& v) {
  const double h = m.grid.cell_size()[0];
  for (int p = 0; p < m.points.size(); ++p) {
    const double x = m.points.position[p][0];
    const int e = static_cast<int>(std::floor(x / h));
    const double xi = x / h - e;
    m.points.velocity[p][0] = (1.0 - xi) * v(e * h) + xi * v((e + 1) * h);
  }
}

/// The kinetic and elastic energy of the points.
double energy(const Model<1>& m) {
  double e = 0.0;
  for (int p = 0; p < m.points.size(); ++p)
    e += 0.5 * m.points.mass[p] * m.points.velocity[p].squaredNorm() + m.elastic_energy(p);
  return e;
}

/// The period of a displacement u(t) sampled after every step, from its zero crossings
/// (linear between the steps; step 1 leaves u = 0 and is skipped).
class ZeroCrossings {
 public:
  void add(int step, double t, double u) {
    if (step > 1 && previous_ * u < 0.0) crossings_.push_back(previous_t_ + (t - previous_t_) * previous_ / (previous_ - u));
    previous_ = u;
    previous_t_ = t;
  }
  std::size_t count() const { return crossings_.size(); }
  /// Two crossings per period, averaged over all of them.
  double period() const { return 2.0 * (crossings_.back() - crossings_.front()) / (crossings_.size() - 1); }

 private:
  std::vector<double> crossings_;
  double previous_ = 0.0, previous_t_ = 0.0;
};

struct Vibration {
  double period = 0.0;       ///< from the zero crossings of the free end's displacement
  double energy_drift = 0.0; ///< max |E(t) - E(0)| / E(0)
};

/// The first mode of the bar excited by its velocity shape, followed for `periods`
/// periods with `per_period` steps each.
Vibration vibrate(int n, bool consistent, int periods, int per_period) {
  Model<1> m = fixed_free_bar(n);
  const double c = 10.0, k = kPi / 2.0, v0 = 1e-6 * c;
  interpolated_velocity(m, [&](double x) { return v0 * std::sin(k * x); });
  const double T = 4.0 / c;
  m.time.dt = T / per_period;
  m.time.end_time = periods * T;
  m.time.consistent_mass = consistent;
  const int tip = m.points.size() - 1;
  const double X = m.points.position[tip][0];
  const double e0 = energy(m);
  ZeroCrossings crossings;
  Vibration out;
  NewtonSettings s;
  run_quasi_static<1>(m, s, [&](const Model<1>& mm, const StepInfo& info) {
    crossings.add(info.step, info.time, mm.points.position[tip][0] - X);
    out.energy_drift = std::max(out.energy_drift, std::abs(energy(mm) - e0) / e0);
  });
  EXPECT_GE(crossings.count(), 2u * periods - 1);
  out.period = crossings.period();
  return out;
}

/// The period of the discrete bar's first mode: the linear basis with element mass
/// rho h [alpha beta; beta alpha] gives omega_h^2 = (c/h)^2 (2 - 2 cos kh) / (2 alpha + 2
/// beta cos kh) (the free end keeps sin(k x_j) a mode: cos kL = 0), and the trapezoidal
/// rule turns it into 2 atan(omega_h dt / 2) / dt.
double discrete_period(int n, bool consistent, double dt) {
  const double c = 10.0, h = 1.0 / n, kh = kPi / 2.0 * h;
  // points at the quarter points of each cell: sum_p m_p N_a N_b
  const double alpha = consistent ? 0.3125 : 0.5, beta = consistent ? 0.1875 : 0.0;
  const double omega = c / h * std::sqrt((2.0 - 2.0 * std::cos(kh)) / (2.0 * alpha + 2.0 * beta * std::cos(kh)));
  return 2.0 * kPi / (2.0 / dt * std::atan(omega * dt / 2.0));
}

}  // namespace

TEST(Dynamics, D1FreeFallIsExact) {
  for (const auto scheme : {TimeSettings::Scheme::Newmark, TimeSettings::Scheme::GeneralisedAlpha})
    for (const bool consistent : {false, true}) {
      Model<2> m(Grid<2>(Vec<2>(0.0, 0.0), Vec<2>(0.5, 0.5), {8, 12}));
      m.materials = {std::make_shared<LinearElastic>(1e6, 0.3, 1000.0)};
      add_regular_points<2>(m.grid, {2, 8}, {6, 10}, 2, [](const Vec<2>&) { return true; }, 0, 1000.0, m.points);
      m.gravity = Vec<2>(0.0, -10.0);
      m.time.dt = 0.05;
      m.time.end_time = 0.8;
      m.time.scheme = scheme;
      m.time.rho_inf = 0.5;
      m.time.consistent_mass = consistent;
      const std::vector<Vec<2>> x0 = m.points.position;
      NewtonSettings s;
      double worst_x = 0.0, worst_v = 0.0;
      run_quasi_static<2>(m, s, [&](const Model<2>& mm, const StepInfo& info) {
        const double t = info.time;
        for (int p = 0; p < mm.points.size(); ++p) {
          const Vec<2> x = x0[p] + Vec<2>(0.0, -5.0 * t * t);
          worst_x = std::max(worst_x, (mm.points.position[p] - x).norm());
          worst_v = std::max(worst_v, (mm.points.velocity[p] - Vec<2>(0.0, -10.0 * t)).norm());
        }
      });
      std::cout << "D1 " << (scheme == TimeSettings::Scheme::Newmark ? "Newmark" : "generalised-alpha") << ", "
                << (consistent ? "consistent" : "lumped") << " mass: fell 3.2 m in 0.8 s; largest error of x "
                << worst_x << " m, of v " << worst_v << " m/s\n";
      EXPECT_LT(worst_x, 1e-12);
      EXPECT_LT(worst_v, 1e-12);
    }
}

TEST(Dynamics, D1AThrownBlockFliesAsAProjectile) {
  CaseFile cf = CaseFile::parse(R"(
[grid]
origin = [0.0, 0.0]
cell_size = 0.5
cells = [12, 12]
[materials.block]
model = "hencky"
young = 1.0e6
poisson = 0.3
density = 1000.0
[[bodies]]
material = "block"
min = [0.5, 0.5]
max = [1.5, 1.5]
velocity = [5.0, 6.0]
[loads]
gravity = [0.0, -10.0]
[time]
dt = 0.05
end_time = 0.8
)",
                                "thrown.toml");
  MpmCase<2> c = read_mpm_case<2>(cf);
  const std::vector<Vec<2>> x0 = c.model.points.position;
  double worst = 0.0;
  run_quasi_static<2>(c.model, c.newton, [&](const Model<2>& m, const StepInfo& info) {
    const double t = info.time;
    for (int p = 0; p < m.points.size(); ++p)
      worst = std::max(worst, (m.points.position[p] - x0[p] - Vec<2>(5.0 * t, 6.0 * t - 5.0 * t * t)).norm());
  });
  std::cout << "D1 a block thrown at (5, 6) m/s: largest departure from x0 + v0 t + g t^2 / 2 over 0.8 s: " << worst
            << " m\n";
  EXPECT_LT(worst, 1e-12);
}

TEST(Dynamics, D2BarPeriodFollowsTheDiscreteClosedForm) {
  const int per_period = 200;
  for (const bool consistent : {false, true}) {
    std::vector<double> errors;
    for (const int n : {4, 8, 16}) {
      const Vibration v = vibrate(n, consistent, 5, per_period);
      const double T = 0.4, discrete = discrete_period(n, consistent, T / per_period);
      errors.push_back(std::abs(v.period / T - 1.0));
      std::cout << "D2 " << (consistent ? "consistent" : "lumped") << " mass, " << 4 * n
                << " cells per wavelength: period " << v.period << " s, " << 100.0 * (v.period / T - 1.0)
                << " % from 4 L / c; discrete closed form " << discrete << " s ("
                << 100.0 * (v.period / discrete - 1.0) << " % from it)\n";
      if (consistent) {
        EXPECT_NEAR(v.period / discrete, 1.0, 1e-6);
        if (4 * n >= 32) EXPECT_LT(errors.back(), 5e-3);
      }
    }
    const double order = std::log2(errors[1] / errors[2]);
    std::cout << "D2 " << (consistent ? "consistent" : "lumped") << " mass: order of convergence " << order << "\n";
    EXPECT_GT(order, 1.8);
    EXPECT_LT(errors.back(), 5e-3);
  }
}

TEST(Dynamics, D2TheSameBarIn2DHasTheSamePeriod) {
  // The bar as a strip of one cell's height in plane strain (nu = 0: no lateral coupling),
  // 2 x 2 points per cell, the nodes at x = 0 held along x: the axial mode's period is the
  // 1D discrete closed form's (the mass and stiffness summed over the strip's height are
  // the 1D chain's).
  const int n = 8, per_period = 200;
  const double h = 1.0 / n, c = 10.0, T = 0.4, k = kPi / 2.0, v0 = 1e-6 * c;
  Model<2> m(Grid<2>(Vec<2>(0.0, 0.0), Vec<2>(h, h), {n + 1, 1}));
  m.materials = {std::make_shared<LinearElastic>(100.0, 0.0, 1.0)};
  add_regular_points<2>(m.grid, {0, 0}, {n, 1}, 2, [](const Vec<2>&) { return true; }, 0, 1.0, m.points);
  m.constraints = {{m.grid.node_index({0, 0}), 0, 0.0}, {m.grid.node_index({0, 1}), 0, 0.0}};
  for (int p = 0; p < m.points.size(); ++p) {  // the interpolant of v0 sin(k x) at the nodes
    const double x = m.points.position[p][0];
    const int e = static_cast<int>(std::floor(x / h));
    const double xi = x / h - e;
    m.points.velocity[p][0] = (1.0 - xi) * v0 * std::sin(k * e * h) + xi * v0 * std::sin(k * (e + 1) * h);
  }
  m.time.dt = T / per_period;
  m.time.end_time = 5 * T;
  m.time.consistent_mass = true;
  const int tip = m.points.size() - 1;
  const double X = m.points.position[tip][0];
  ZeroCrossings crossings;
  NewtonSettings s;
  run_quasi_static<2>(m, s, [&](const Model<2>& mm, const StepInfo& info) {
    crossings.add(info.step, info.time, mm.points.position[tip][0] - X);
  });
  const double period = crossings.period();
  const double discrete = discrete_period(n, true, T / per_period);
  std::cout << "D2 2D strip, consistent mass, 32 cells per wavelength: period " << period << " s, the 1D discrete "
            << "closed form " << discrete << " s (" << 100.0 * (period / discrete - 1.0) << " % from it)\n";
  EXPECT_NEAR(period / discrete, 1.0, 1e-6);
}

TEST(Dynamics, D3TrapezoidalRuleConservesEnergy) {
  const int periods = 20;
  const Vibration v = vibrate(8, true, periods, 50);
  std::cout << "D3 consistent mass, trapezoidal rule, 20 periods of 50 steps: largest |E - E0| / E0 = "
            << v.energy_drift << "\n";
  EXPECT_LT(v.energy_drift, 1e-6 * periods);
  EXPECT_LT(v.energy_drift / periods, 1e-6);
}

namespace {

/// Generalised-alpha (Chung & Hulbert 1993, the forces interpolated) on m a + k u = 0:
/// one step from (u, v, a).
std::array<double, 3> alpha_step(const TimeSettings& t, double m, double k, std::array<double, 3> x) {
  const auto [am, af, beta, gamma] = t.coefficients();
  const double dt = t.dt, u = x[0], v = x[1], a = x[2];
  const double U = u + dt * v + dt * dt * (0.5 - beta) * a;
  const double a1 = -(am * m * a + (1.0 - af) * k * U + af * k * u) / ((1.0 - am) * m + (1.0 - af) * k * beta * dt * dt);
  return {U + beta * dt * dt * a1, v + dt * ((1.0 - gamma) * a + gamma * a1), a1};
}

}  // namespace

TEST(Dynamics, D4GeneralisedAlphaDampsTheHighestMode) {
  for (const double rho_inf : {1.0, 0.5, 0.0}) {
    // One cell of E = 1e6 fixed at x = 0: one free dof, consistent mass m = sum_p m_p N_p1^2
    // = 0.3125, k = E / h = 1e6; with dt = 1, omega dt = 1789.
    Model<1> m = fixed_free_bar(1, 1e6);
    for (int p = 0; p < m.points.size(); ++p) m.points.velocity[p][0] = 1e-3 * m.points.position[p][0];
    m.time.dt = 1.0;
    m.time.end_time = 20.0;
    m.time.scheme = TimeSettings::Scheme::GeneralisedAlpha;
    m.time.rho_inf = rho_inf;
    m.time.consistent_mass = true;
    const int tip = m.points.size() - 1;
    const double X = m.points.position[tip][0];
    std::vector<double> u;
    NewtonSettings s;
    run_quasi_static<1>(m, s, [&](const Model<1>& mm, const StepInfo&) { u.push_back(mm.points.position[tip][0] - X); });
    // The same steps of the scheme on the single dof, and its spectral radius at this omega dt.
    const double mass = 0.3125, k = 1e6;
    std::array<double, 3> x{0.0, 1e-3, 0.0};
    double worst = 0.0, largest = 0.0;
    for (std::size_t n = 0; n < u.size(); ++n) {
      x = alpha_step(m.time, mass, k, x);
      worst = std::max(worst, std::abs(u[n] - X * x[0]));
      largest = std::max(largest, std::abs(X * x[0]));
    }
    Eigen::Matrix3d A;
    for (int j = 0; j < 3; ++j) {
      std::array<double, 3> e{0.0, 0.0, 0.0};
      e[j] = 1.0;
      const auto y = alpha_step(m.time, mass, k, e);
      for (int i = 0; i < 3; ++i) A(i, j) = y[i];
    }
    const double radius = A.eigenvalues().cwiseAbs().maxCoeff();
    std::cout << "D4 generalised-alpha, rho_inf " << rho_inf << ", omega dt = 1789: spectral radius " << radius
              << "; the MPM run follows the scheme's recurrence to " << worst / largest << " of its amplitude\n";
    EXPECT_NEAR(radius, rho_inf, 0.01);
    EXPECT_LT(worst, 1e-6 * largest);
  }
}

TEST(Dynamics, D5ADampedColumnComesToRestCarryingItsWeight) {
  // x in [0, 1], fixed at x = 0, gravity -10 along x; E = 1e4, rho = 1: c = 100, the
  // first period 4 L / c = 0.04; alpha = 50 1/s damps it by e^-1 in 0.04 s.
  Model<1> m = fixed_free_bar(16, 1e4);
  m.gravity = Vec<1>(-10.0);
  m.time.dt = 0.002;
  m.time.end_time = 5.0;
  m.time.damping = 50.0;
  m.time.stop_at_rest = 1e-8;
  NewtonSettings s;
  double weight = 0.0, base = 0.0, peak = 0.0, kinetic = 0.0, t = 0.0;
  for (int p = 0; p < m.points.size(); ++p) weight += 10.0 * m.points.mass[p];
  bool rest = false;
  run_quasi_static<1>(m, s, [&](const Model<1>&, const StepInfo& info) {
    peak = std::max(peak, info.kinetic_energy);
    kinetic = info.kinetic_energy;
    t = info.time;
    rest = info.at_rest;
    base = info.grid_reaction()[0];
  });
  std::cout << "D5 at rest at t = " << t << " (kinetic energy " << kinetic / peak << " of its peak); base reaction "
            << base << " against the weight " << weight << "\n";
  EXPECT_TRUE(rest);
  EXPECT_LT(t, 5.0);
  EXPECT_LE(kinetic, 1e-8 * peak);
  EXPECT_NEAR(base / weight, 1.0, 1e-3);
}

namespace {

/// The cantilever x in [0, 1], y in [0, 0.05], clamped at x = 0, `layers` cells through the
/// thickness; the period of its free end's transverse motion over five periods.
double cantilever_period(int layers, bool consistent) {
  const double h = 0.05 / layers;
  const int last = 4 * static_cast<int>(std::lround(1.0 / h)) * layers - 1;  // the top corner's point
  CaseFile cf = CaseFile::parse(fmt::format(R"(
[grid]
origin = [{0}, {1}]
cell_size = {2}
cells = [{3}, {4}]
[materials.beam]
model = "linear-elastic"
young = 1.0e6
poisson = 0.0
density = 1000.0
[[bodies]]
material = "beam"
min = [0.0, 0.0]
max = [1.0, 0.05]
velocity = [0.0, 1.0e-4]
[[constraints]]
min = [{0}, {1}]
max = [0.0, 0.1]
fix = ["x", "y"]
[time]
dt = 0.04
end_time = 20.0
mass = "{5}"
)",
                                            -h, -2 * h, h, static_cast<int>(std::lround(1.0 / h)) + 4, layers + 4,
                                            consistent ? "consistent" : "lumped"),
                                "cantilever.toml");
  MpmCase<2> c = read_mpm_case<2>(cf);
  const double y0 = c.model.points.position[last][1];
  ZeroCrossings crossings;
  run_quasi_static<2>(c.model, c.newton, [&](const Model<2>& m, const StepInfo& info) {
    crossings.add(info.step, info.time, m.points.position[last][1] - y0);
  });
  return crossings.period();
}

}  // namespace

TEST(Dynamics, D6CantileverVibratesAtTheEulerBernoulliFrequency) {
  const double E = 1e6, rho = 1000.0, t = 0.05, I = t * t * t / 12.0;
  const double omega = 1.875104 * 1.875104 * std::sqrt(E * I / (rho * t));
  const double T = 2.0 * kPi / omega;
  for (const auto& [layers, consistent] : std::vector<std::pair<int, bool>>{{4, true}, {8, true}, {8, false}}) {
    const double period = cantilever_period(layers, consistent);
    std::cout << "D6 cantilever, " << layers << " cells through the thickness, " << (consistent ? "consistent" : "lumped")
              << " mass: period " << period << " s against Euler-Bernoulli " << T << " s ("
              << 100.0 * (period / T - 1.0) << " %)\n";
    EXPECT_NEAR(period / T, 1.0, 0.02);
  }
}
