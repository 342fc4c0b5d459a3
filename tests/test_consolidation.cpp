// Requirements of the coupled displacement-pressure (u-p) MPM ([pore_pressure];
// mpm/Consolidation.hpp, docs/pore-pressure.md):
//   C1 Terzaghi's 1D consolidation (a column of height H drained at its top, loaded by q at
//      t = 0; 160 cells, dt = 0.001 H^2 / c_v): the isochrones p(z, t) are the series
//      solution's within 1 % of p_0, and the degree of consolidation, from the pore pressure
//      and from the settlement (between the undrained and the drained runs'), within 1 % of
//      U(T_v), at T_v = 0.05, 0.2 and 1;
//   C2 undrained loading (k = 0): the pore pressure is p_0 = q m_v / (m_v + n / K_f), to
//      1e-9 in the column's lower half (1e-3 below the top 5 cells: the point load starts a
//      checkerboard that the pressure projection damps), and the solid carries the rest;
//   C3 the drained limit: one time step far longer than H^2 / c_v gives the drained run's
//      settlement (no pore pressure) to 1e-6 and leaves p below 1e-6 p_0;
//   C4 at finite strain (Hencky, a load of 0.3 E, drained at the base) Newton converges
//      quadratically on the coupled system: the consistent tangent of the pore pressure on
//      the current volume;
//   C6 Kozeny-Carman: a column whose points start compressed to J = 0.9 (porosity 1/3 from
//      0.4) consolidates with k scaled by (n^3 / (1 - n)^2) / (n_0^3 / (1 - n_0)^2) = 0.469
//      and the storage of its porosity: the isochrones are Terzaghi's at that c_v within
//      1 % of p_0 (T_v = 0.05, 0.2, 1);
//   C7 at rest under gravity (a saturated column of density 2 rho_w, drained at its top)
//      the pore pressure is hydrostatic, rho_w g (H - X), to 1e-3 rho_w g H, and the
//      effective stress carries the buoyant weight (rho - rho_w) g (H - X) to 1e-2 of it;
//   C8 large-strain 1D consolidation (Gibson, England & Hussey 1967): a Hencky column
//      (nu = 0, no body force, incompressible constituents, constant k) loaded by 0.3 E and
//      drained at its fixed base compresses by a quarter. The settlement and the pore
//      pressure follow Gibson's equation in the material coordinate,
//        d lambda / dt = (k / gamma_w) d/dZ [ (1 / lambda) d/dZ (E ln lambda / lambda) ],
//      p = E ln lambda / lambda + q, solved by finite differences in the test (uGIMP, 160
//      cells): the settlement within 1 % of its final value and p within 2 % of q at
//      T = 0.05, 0.2, 1 (T = k E t / (gamma_w H^2); the final settlement is 0.211 H, the
//      small-strain theory's 0.3 H);
//   C5 Mandel's problem (plane strain, a quarter of the sample, a rigid frictionless plate
//      on top by node ties, drained at x = a): the pore pressure at the centre follows
//      Mandel's closed form (Abousleiman et al. 1996) within 2 % of p_0 from T = 0.005 to
//      0.5, rising above its initial value (the Mandel-Cryer effect) by more than 8 %.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <iostream>
#include <numbers>

#include "gradmpm/materials/Hencky.hpp"
#include "gradmpm/materials/LinearElastic.hpp"
#include "gradmpm/mpm/QuasiStatic.hpp"
#include "gradmpm/points/Generate.hpp"
#include "gradmpm/solver/SparsePattern.hpp"

using namespace gradmpm;

namespace {

constexpr double kPi = std::numbers::pi;

/// The column: H = 1 on n cells of 2 points, fixed and impermeable at x = 0, drained at
/// x = H, the load q on its top point; E = 1e7, n = 0.4, K_f = 2.2e9, gamma_w = 9806.65 and
/// the conductivity that makes c_v = k / (gamma_w (m_v + S)) = 1.
struct Column {
  static constexpr double H = 1.0, E = 1e7, q = 1e4, porosity = 0.4, Kf = 2.2e9, rho_w = 1000.0;
  static double storage() { return porosity / Kf; }
  static double mv() { return 1.0 / E; }
  static double p0() { return q * mv() / (mv() + storage()); }
  static double conductivity() { return rho_w * 9.80665 * (mv() + storage()); }
};

Model<1> column(int n, PoreSettings::Drainage drainage, bool finite = false, double q = Column::q) {
  const double h = Column::H / n;
  Model<1> m(Grid<1>(Vec<1>(0.0), Vec<1>(h), {n}));
  if (finite)
    m.materials = {std::make_shared<Hencky>(Column::E, 0.0, 0.0)};
  else
    m.materials = {std::make_shared<LinearElastic>(Column::E, 0.0, 0.0)};
  add_regular_points<1>(m.grid, {0}, {n}, 2, [](const Vec<1>&) { return true; }, 0, 0.0, m.points);
  m.points.force.back()[0] = -q;
  m.constraints = {{0, 0, 0.0}};
  m.pore.drainage = drainage;
  m.pore.fluids = {PoreFluid{drainage == PoreSettings::Drainage::Coupled ? Column::conductivity() : 0.0, Column::Kf,
                             Column::porosity, Column::rho_w}};
  m.pore.constraints = {{n, 0.0}};
  return m;
}

/// Terzaghi's series: p(z, T) / p_0 with z from the drained face, and U(T).
double terzaghi_p(double z, double T) {
  double p = 0.0;
  for (int k = 0; k < 4000; ++k) {
    const double M = kPi * (2 * k + 1) / 2.0;
    p += 2.0 / M * std::sin(M * z / Column::H) * std::exp(-M * M * T);
  }
  return p;
}
double terzaghi_U(double T) {
  double u = 1.0;
  for (int k = 0; k < 4000; ++k) {
    const double M = kPi * (2 * k + 1) / 2.0;
    u -= 2.0 / (M * M) * std::exp(-M * M * T);
  }
  return u;
}

/// The column's settlement: its loss of height, sum_p (V_p - v_p) per unit area.
double top_settlement(const Model<1>& m) {
  double s = 0.0;
  for (int p = 0; p < m.points.size(); ++p) s += m.points.original_volume[p] - m.points.volume[p];
  return s;
}

/// The settlement of a run in load steps (drained, or undrained: no time).
double settlement_in_one_step(PoreSettings::Drainage drainage, int n = 40) {
  Model<1> m = column(n, drainage);
  m.pore.constraints.clear();  // (undrained: at t = 0+, before any flow)
  NewtonSettings s;
  s.load_steps = 1;
  run_quasi_static<1>(m, s);
  return top_settlement(m);
}

}  // namespace

TEST(Consolidation, C1_TerzaghiIsochronesAndDegreeOfConsolidation) {
  const int n = 160;
  Model<1> m = column(n, PoreSettings::Drainage::Coupled);
  m.time.dt = 1e-3;
  m.time.end_time = 1.0;
  m.time.inertia = false;
  const double s_undrained = settlement_in_one_step(PoreSettings::Drainage::Undrained, n);
  const double s_drained = settlement_in_one_step(PoreSettings::Drainage::Drained, n);
  const double p0 = Column::p0();
  std::vector<double> targets = {0.05, 0.2, 1.0};
  std::size_t next = 0;
  NewtonSettings s;
  std::cout << "  T_v     max|p - p_T| / p_0   U_p       U_s       U(T_v)\n";
  run_quasi_static<1>(m, s, [&](const Model<1>& mm, const StepInfo& info) {
    if (next == targets.size() || std::abs(info.time - targets[next]) > 1e-9) return;
    const double T = targets[next++];  // (c_v = 1, H = 1)
    double error = 0.0, integral = 0.0;
    for (int p = 0; p < mm.points.size(); ++p) {
      const double expected = p0 * terzaghi_p(Column::H - mm.points.original_position[p][0], T);
      error = std::max(error, std::abs(mm.points.pore_pressure[p] - expected) / p0);
      integral += mm.points.pore_pressure[p] * mm.points.original_volume[p];
    }
    const double U_p = 1.0 - integral / (p0 * Column::H);
    const double U_s = (top_settlement(mm) - s_undrained) / (s_drained - s_undrained);
    const double U = terzaghi_U(T);
    std::cout << fmt::format("  {:<6g}  {:<19.2e}  {:<8.5f}  {:<8.5f}  {:.5f}\n", T, error, U_p, U_s, U);
    EXPECT_LT(error, 0.01) << "T_v = " << T;
    EXPECT_NEAR(U_p, U, 0.01 * U) << "T_v = " << T;
    EXPECT_NEAR(U_s, U, 0.01 * U) << "T_v = " << T;
  });
  EXPECT_EQ(next, targets.size());
}

TEST(Consolidation, C2_UndrainedLoadingLeavesTheSolidTheSkeletonsShare) {
  Model<1> m = column(40, PoreSettings::Drainage::Undrained);
  m.pore.constraints.clear();  // (undrained: no face drains either)
  NewtonSettings s;
  s.load_steps = 1;
  run_quasi_static<1>(m, s);
  const double p0 = Column::p0(), h = Column::H / 40;
  // The point load on one point starts a checkerboard in p (every other point) that the
  // projection damps by about 3 per cell: measured below the top 5 cells, asserted in the
  // lower half.
  double near = 0.0, far = 0.0, far_stress = 0.0;
  for (int p = 0; p < m.points.size(); ++p) {
    const double X = m.points.original_position[p][0];
    const double error = std::abs(m.points.pore_pressure[p] - p0) / p0;
    if (X < Column::H - 5.0 * h) near = std::max(near, error);
    if (X > Column::H / 2.0) continue;
    far = std::max(far, error);
    far_stress = std::max(far_stress, std::abs(m.points.stress[p](0, 0) + (Column::q - p0)) / Column::q);
  }
  std::cout << fmt::format(
      "  |p / p_0 - 1| below the top 5 cells {:.2e}, in the lower half {:.2e}; effective stress off by {:.2e} q\n",
      near, far, far_stress);
  EXPECT_LT(far, 1e-9);
  EXPECT_LT(far_stress, 1e-9);
  EXPECT_LT(near, 1e-3);
}

TEST(Consolidation, C3_OneLongTimeStepReachesTheDrainedSettlement) {
  Model<1> m = column(40, PoreSettings::Drainage::Coupled);
  m.time.dt = 1e6;
  m.time.end_time = 1e6;
  m.time.inertia = false;
  run_quasi_static<1>(m, NewtonSettings{});
  const double s_drained = settlement_in_one_step(PoreSettings::Drainage::Drained);
  double p_max = 0.0;
  for (double p : m.points.pore_pressure) p_max = std::max(p_max, std::abs(p));
  std::cout << fmt::format("  settlement {:.9e} (drained {:.9e}); max |p| / p_0 = {:.2e}\n", top_settlement(m),
                           s_drained, p_max / Column::p0());
  EXPECT_NEAR(top_settlement(m), s_drained, 1e-6 * s_drained);
  EXPECT_LT(p_max, 1e-6 * Column::p0());
}

TEST(Consolidation, C4_FiniteStrainNewtonConvergesQuadratically) {
  Model<1> m = column(20, PoreSettings::Drainage::Coupled, true, 0.3 * Column::E);
  m.pore.constraints = {{0, 0.0}};  // drained at the fixed base: the top settles off its node
  m.time.dt = 0.01;
  m.time.end_time = 0.1;
  m.time.inertia = false;
  int checked = 0;
  NewtonSettings s;
  s.tolerance = 1e-12;
  run_quasi_static<1>(m, s, [&](const Model<1>&, const StepInfo& info) {
    const auto& r = info.residuals;
    ASSERT_LE(r.size(), 8u) << "step " << info.step;
    // Quadratic: once below 1e-2, each residual at most ~ the square of the one before.
    for (std::size_t k = 2; k < r.size(); ++k)
      if (r[k - 1] < 1e-2 && r[k] > 1e-14) {
        EXPECT_LT(r[k], 10.0 * r[k - 1] * r[k - 1]) << "step " << info.step << ", iteration " << k;
        ++checked;
      }
  });
  std::cout << fmt::format("  {} quadratic iterations checked; settlement {:.4f} H\n", checked, top_settlement(m));
  EXPECT_GT(checked, 0);
  // Compressed by 0.3 E: the column's final strain is far beyond small strain.
  EXPECT_GT(top_settlement(m), 0.01);
}

namespace {

/// Mandel's problem: a sample of half-width a between rigid frictionless plates loaded by
/// 2F (per unit depth) at t = 0, drained at its sides. With Biot's coefficient 1 and
/// incompressible grains (Abousleiman, Cheng, Cui, Detournay & Roegiers 1996, eq. 21-22):
/// p(x, t) = 2 F B (1 + nu_u) / (3 a) sum_n sin a_n / (a_n - sin a_n cos a_n)
///           (cos(a_n x / a) - cos a_n) exp(-a_n^2 c t / a^2),
/// tan a_n = (1 - nu) / (nu_u - nu) a_n, c = 2 kappa B^2 G (1 - nu)(1 + nu_u)^2 / (9 (1 - nu_u)(nu_u - nu)).
struct Mandel {
  double E = 1e7, nu = 0.2, porosity = 0.4, Kf = 2.2e9, k = 1e-4, gamma_w = 1000.0 * 9.80665, a = 1.0, F = 1e4;
  double G, B, nu_u, c;
  std::vector<double> roots;
  Mandel() {
    G = E / (2.0 * (1.0 + nu));
    const double K = E / (3.0 * (1.0 - 2.0 * nu)), M = Kf / porosity;
    B = M / (K + M);
    nu_u = (3.0 * nu + B * (1.0 - 2.0 * nu)) / (3.0 - B * (1.0 - 2.0 * nu));
    c = 2.0 * (k / gamma_w) * B * B * G * (1.0 - nu) * (1.0 + nu_u) * (1.0 + nu_u) / (9.0 * (1.0 - nu_u) * (nu_u - nu));
    const double r = (1.0 - nu) / (nu_u - nu);
    for (int i = 1; i <= 400; ++i) {  // one root in ((i - 1) pi, (i - 1/2) pi)
      double lo = (i - 1) * kPi + 1e-12, hi = (i - 0.5) * kPi - 1e-12;
      for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        (std::tan(mid) - r * mid < 0.0 ? lo : hi) = mid;
      }
      roots.push_back(0.5 * (lo + hi));
    }
  }
  double p0() const { return F * B * (1.0 + nu_u) / (3.0 * a); }
  double p(double x, double t) const {
    double sum = 0.0;
    for (double an : roots)
      sum += std::sin(an) / (an - std::sin(an) * std::cos(an)) * (std::cos(an * x / a) - std::cos(an)) *
             std::exp(-an * an * c * t / (a * a));
    return 2.0 * p0() * sum;
  }
};

}  // namespace

TEST(Consolidation, C5_MandelsProblemShowsTheMandelCryerEffect) {
  const Mandel mandel;
  const int n = 20;
  const double h = mandel.a / n;
  // The sample is 2a tall (Mandel's solution does not depend on its height): the load
  // reaches the plate through the top row of points, a quarter of it through the node
  // row below the plate, and that disturbs p within about a of the plate (at T = 0.05,
  // 1.042 p_0 under the plate, 1.103 at the centre of a sample 2a wide and a tall).
  const int rows = 2 * n;
  Model<2> m(Grid<2>(Vec<2>(0.0, 0.0), Vec<2>(h, h), {n, rows}));
  m.materials = {std::make_shared<LinearElastic>(mandel.E, mandel.nu, 0.0)};
  add_regular_points<2>(m.grid, {0, 0}, {n, rows}, 2, [](const Vec<2>&) { return true; }, 0, 0.0, m.points);
  for (int p = 0; p < m.points.size(); ++p)  // F on the top row of points
    if (m.points.position[p][1] > rows * h - h / 2) m.points.force[p][1] = -mandel.F / (2 * n);
  for (int node = 0; node < m.grid.num_nodes(); ++node) {
    const auto ijk = m.grid.node_ijk(node);
    if (ijk[0] == 0) m.constraints.push_back({node, 0, 0.0});  // symmetry x = 0
    if (ijk[1] == 0) m.constraints.push_back({node, 1, 0.0});  // symmetry y = 0
    if (ijk[0] == n) m.pore.constraints.push_back({node, 0.0});  // drained side
    if (ijk[1] == rows && ijk[0] < n)                             // the plate
      m.ties.push_back({node, m.grid.node_index({ijk[0] + 1, rows}), 1, 1e4 * mandel.E});
  }
  m.pore.drainage = PoreSettings::Drainage::Coupled;
  m.pore.fluids = {PoreFluid{mandel.k, mandel.Kf, mandel.porosity, 1000.0}};
  const double t_ref = mandel.a * mandel.a / mandel.c;  // T = c t / a^2
  m.time.dt = 0.005 * t_ref;
  m.time.end_time = 0.5 * t_ref;
  m.time.inertia = false;
  const double p0 = mandel.p0();
  double worst = 0.0, peak = 0.0;
  std::cout << "  T       p(centre) / p_0   Mandel\n";
  run_quasi_static<2>(m, NewtonSettings{}, [&](const Model<2>& mm, const StepInfo& info) {
    // the centre: the points of the first column (x = h / 4) in the lower quarter, their mean
    double sum = 0.0, x = 0.0;
    int count = 0;
    for (int p = 0; p < mm.points.size(); ++p)
      if (mm.points.original_position[p][0] < h / 2 && mm.points.original_position[p][1] < mandel.a / 2) {
        sum += mm.points.pore_pressure[p];
        x += mm.points.position[p][0];
        ++count;
      }
    const double centre = sum / count / p0, exact = mandel.p(x / count, info.time) / p0;
    worst = std::max(worst, std::abs(centre - exact));
    peak = std::max(peak, centre);
    if (info.step == 1 || info.step % 10 == 0)
      std::cout << fmt::format("  {:<6.3f}  {:<16.4f}  {:.4f}\n", info.time / t_ref, centre, exact);
  });
  std::cout << fmt::format("  largest error {:.4f} p_0; peak p / p_0 = {:.4f}\n", worst, peak);
  EXPECT_LT(worst, 0.02);
  EXPECT_GT(peak, 1.08);
}

TEST(Consolidation, C6_KozenyCarmanScalesTheConductivityWithThePorosity) {
  const int n = 160;
  Model<1> m = column(n, PoreSettings::Drainage::Coupled);
  m.pore.fluids[0].kozeny_carman = true;
  const double J = 0.9;
  for (int p = 0; p < m.points.size(); ++p) {  // compressed to J at the start: V_0 = v / J
    m.points.F[p](0, 0) = J;
    m.points.original_volume[p] = m.points.volume[p] / J;
  }
  const double n0 = Column::porosity, por = 1.0 - (1.0 - n0) / J;
  const double factor = (por * por * por / ((1 - por) * (1 - por))) / (n0 * n0 * n0 / ((1 - n0) * (1 - n0)));
  const double S = por / Column::Kf;
  const double cv = factor * Column::conductivity() / (1000.0 * 9.80665 * (Column::mv() + S));
  const double p0 = Column::q * Column::mv() / (Column::mv() + S);
  m.time.dt = 0.002;
  m.time.end_time = 1.0 / cv + 0.002;
  m.time.inertia = false;
  std::vector<double> targets = {0.05, 0.2, 1.0};
  std::size_t next = 0;
  std::cout << fmt::format("  k / k_0 = {:.5f}, c_v = {:.5f}\n  T_v      max|p - p_T| / p_0\n", factor, cv);
  run_quasi_static<1>(m, NewtonSettings{}, [&](const Model<1>& mm, const StepInfo& info) {
    if (next == targets.size() || cv * info.time < targets[next]) return;
    const double T = cv * info.time;  // (the first step at or past the target)
    ++next;
    double error = 0.0;
    for (int p = 0; p < mm.points.size(); ++p) {
      const double expected = p0 * terzaghi_p(Column::H - mm.points.original_position[p][0], T);
      error = std::max(error, std::abs(mm.points.pore_pressure[p] - expected) / p0);
    }
    std::cout << fmt::format("  {:<7.4f}  {:.2e}\n", T, error);
    EXPECT_LT(error, 0.01) << "T_v = " << T;
  });
  EXPECT_EQ(next, targets.size());
}

TEST(Consolidation, C7_AtRestUnderGravityThePorePressureIsHydrostatic) {
  Model<1> m = column(40, PoreSettings::Drainage::Coupled);
  const double rho = 2000.0, g = 9.81;
  m.materials = {std::make_shared<LinearElastic>(Column::E, 0.0, rho)};
  for (int p = 0; p < m.points.size(); ++p) {
    m.points.mass[p] = rho * m.points.volume[p];
    m.points.force[p].setZero();
  }
  m.gravity = Vec<1>(-g);
  m.pore.gravity = g;
  m.time.dt = 1e6;  // (one step to the state at rest)
  m.time.end_time = 1e6;
  m.time.inertia = false;
  run_quasi_static<1>(m, NewtonSettings{});
  const double gw = Column::rho_w * g;
  double p_error = 0.0, s_error = 0.0;
  for (int p = 0; p < m.points.size(); ++p) {
    const double depth = Column::H - m.points.original_position[p][0];
    p_error = std::max(p_error, std::abs(m.points.pore_pressure[p] - gw * depth) / (gw * Column::H));
    s_error = std::max(s_error, std::abs(m.points.stress[p](0, 0) + (rho * g - gw) * depth) / ((rho * g - gw) * Column::H));
  }
  std::cout << fmt::format("  p off rho_w g (H - X) by at most {:.2e} rho_w g H; effective stress off by {:.2e}\n",
                           p_error, s_error);
  EXPECT_LT(p_error, 1e-3);
  EXPECT_LT(s_error, 1e-2);
}

namespace {

/// Gibson, England & Hussey's large-strain consolidation of a weightless layer in its
/// material coordinate Z (0: the drained, fixed base; H: the loaded top, impermeable),
/// with Hencky's effective Cauchy stress s(lambda) = E ln(lambda) / lambda (nu = 0, 1D)
/// and a constant conductivity: d lambda / dt = c d/dZ ((1 / lambda) ds/dZ), c = k / gamma_w,
/// lambda = 1 at t = 0+ (undrained, incompressible) and s(lambda) = -q at the base.
/// Explicit finite differences on n + 1 nodes.
struct Gibson {
  double E, q, c, H;
  int n = 200;
  std::vector<double> lambda;
  double t = 0.0;

  Gibson(double E_, double q_, double c_, double H_) : E(E_), q(q_), c(c_), H(H_), lambda(n + 1, 1.0) {
    double l = 1.0;  // the base: E ln(l) / l = -q, by Newton
    for (int it = 0; it < 50; ++it) l -= (E * std::log(l) / l + q) / (E * (1.0 - std::log(l)) / (l * l));
    lambda[0] = l;
  }
  double stress(double l) const { return E * std::log(l) / l; }
  void advance_to(double t_end) {
    const double h = H / n, l_min = lambda[0];
    const double D = c * E * (1.0 - std::log(l_min)) / (l_min * l_min * l_min);  // the largest diffusivity
    const double dt_max = 0.2 * h * h / D;
    std::vector<double> flux(n + 1, 0.0);  // flux[i]: between nodes i - 1 and i
    while (t < t_end) {
      const double dt = std::min(dt_max, t_end - t);
      for (int i = 1; i <= n; ++i)
        flux[i] = 2.0 / (lambda[i] + lambda[i - 1]) * (stress(lambda[i]) - stress(lambda[i - 1])) / h;
      for (int i = 1; i < n; ++i) lambda[i] += dt * c * (flux[i + 1] - flux[i]) / h;
      lambda[n] += dt * c * (0.0 - flux[n]) / (0.5 * h);  // the impermeable top: no flux out
      t += dt;
    }
  }
  double settlement() const {
    const double h = H / n;
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += 0.5 * h * ((1.0 - lambda[i]) + (1.0 - lambda[i + 1]));
    return s;
  }
  double pressure(double Z) const {  // p = s(lambda) + q, linear between nodes
    const double x = std::clamp(Z / (H / n), 0.0, double(n) - 1e-12);
    const int i = static_cast<int>(x);
    const double w = x - i;
    return stress((1.0 - w) * lambda[i] + w * lambda[i + 1]) + q;
  }
};

}  // namespace

TEST(Consolidation, C8_LargeStrainConsolidationFollowsGibson) {
  const int cells = 160;
  const double q = 0.3 * Column::E, gamma_w = 1000.0 * 9.80665;
  // uGIMP, on a grid with a cell below the fixed, drained base for the lowest points'
  // domains. With the linear basis the points' effective stress is noisy once they cross
  // cells (J from 0.89 to 1.006 side by side), and p lags Gibson's by up to 0.46 q.
  const double h = Column::H / cells;
  Model<1> m(Grid<1>(Vec<1>(-h), Vec<1>(h), {cells + 1}));
  m.basis = BasisKind::UGIMP;
  m.materials = {std::make_shared<Hencky>(Column::E, 0.0, 0.0)};
  add_regular_points<1>(m.grid, {1}, {cells + 1}, 2, [](const Vec<1>&) { return true; }, 0, 0.0, m.points);
  m.points.force.back()[0] = -q;
  m.constraints = {{0, 0, 0.0}, {1, 0, 0.0}};
  m.pore.drainage = PoreSettings::Drainage::Coupled;
  // incompressible, as Gibson's theory; k = gamma_w / E, so that T = t
  m.pore.fluids = {PoreFluid{gamma_w / Column::E, 1e20, Column::porosity, Column::rho_w}};
  m.pore.constraints = {{0, 0.0}, {1, 0.0}};
  m.time.dt = 1e-3;
  m.time.end_time = 1.0;
  m.time.inertia = false;
  Gibson reference(Column::E, q, 1.0 / Column::E, Column::H);
  const double s_final = Column::H * (1.0 - reference.lambda[0]);  // (at rest: lambda the base's everywhere)
  const std::vector<double> targets = {0.05, 0.2, 1.0};
  std::size_t next = 0;
  std::cout << fmt::format("  final settlement {:.5f} H (small strain: {:.5f} H)\n", s_final, q / Column::E)
            << "  T        settlement (MPM, Gibson)     max|p - p_Gibson| / q\n";
  run_quasi_static<1>(m, NewtonSettings{}, [&](const Model<1>& mm, const StepInfo& info) {
    if (next == targets.size() || std::abs(info.time - targets[next]) > 1e-9) return;
    const double T = targets[next++];
    reference.advance_to(T);
    double error = 0.0;
    for (int p = 0; p < mm.points.size(); ++p)
      error = std::max(error, std::abs(mm.points.pore_pressure[p] - reference.pressure(mm.points.original_position[p][0])) / q);
    const double s = top_settlement(mm), s_ref = reference.settlement();
    std::cout << fmt::format("  {:<7.3f}  {:.5f}  {:.5f}           {:.2e}\n", T, s, s_ref, error);
    EXPECT_LT(std::abs(s - s_ref), 0.01 * s_final) << "T = " << T;
    EXPECT_LT(error, 0.02) << "T = " << T;
  });
  EXPECT_EQ(next, targets.size());
}
