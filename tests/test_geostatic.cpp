// Requirements of the geostatic initial stresses ([initial_stress]; mpm/InitialStress.hpp,
// docs/pore-pressure.md "Initial stresses"):
//   G1 a block of elastic soil (plane strain, nu = 0.3, K0 = nu / (1 - nu)) starts at
//      sigma_v = rho g d and sigma_h = K0 sigma_v at every point (to 1e-12 rho g H); load
//      steps with gravity as the only (dead) load leave it where it is: the displacements
//      stay below 1e-3 of the settlement gravity ramped from zero gives, and the stresses
//      within 1e-2 rho g H of the geostatic ones;
//   G6 the same block as an axisymmetric cylinder (r-z, x the radius, on its axis): the
//      per-radian column weights give the same stresses (sigma_rr = sigma_thetatheta =
//      K0 sigma_v, to 1e-12 rho g H), and it stays at rest as G1's does;
//   G2 a saturated column (water table at its top) starts with a hydrostatic pore pressure
//      and the buoyant effective stress, and stays there through a consolidation step: p to
//      1e-6 rho_w g H, the settlement below 1e-3 of the drained one under its weight;
//   G3 Modified Cam-Clay started from a K0 stress gives the stress back at rest, and its
//      preconsolidation pressure is OCR (P + q^2 / (M^2 P)): on the yield surface when
//      normally consolidated (|f| <= 1e-12 P^2), inside it when OCR = 2;
//   G5 a strip load on a layer of overconsolidated Modified Cam-Clay (OCR 4: it stays
//      elastic) consolidating from its geostatic state (water table at the surface, which
//      drains): the settlement under the load grows from above the undrained run's (k = 0)
//      after the load's step and ends at the drained run's (the same layer at its buoyant
//      weight, no pore pressure) within 1 %;
//   G4 a stress outside a law's yield surface (Mohr-Coulomb, K0 = 0.1 for phi = 30 deg and a
//      small cohesion) is refused with a message naming the point and the law.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "gradmpm/materials/Hencky.hpp"
#include "gradmpm/materials/LinearElastic.hpp"
#include "gradmpm/materials/ModifiedCamClay.hpp"
#include "gradmpm/materials/MohrCoulomb.hpp"
#include "gradmpm/mpm/InitialStress.hpp"
#include "gradmpm/mpm/QuasiStatic.hpp"
#include "gradmpm/points/Generate.hpp"

using namespace gradmpm;

namespace {

constexpr double kRho = 2000.0, kG = 9.81, kE = 1e7, kNu = 0.3;

/// Gravity -y; the grid's base fixed, its sides on rollers.
void support(Model<2>& m) {
  m.gravity = Vec<2>(0.0, -kG);
  const auto n = m.grid.cells();
  for (int i = 0; i <= n[0]; ++i) {
    m.constraints.push_back({m.grid.node_index({i, 0}), 0, 0.0});
    m.constraints.push_back({m.grid.node_index({i, 0}), 1, 0.0});
  }
  for (int j = 1; j <= n[1]; ++j) {
    m.constraints.push_back({m.grid.node_index({0, j}), 0, 0.0, true});
    m.constraints.push_back({m.grid.node_index({n[0], j}), 0, 0.0, true});
  }
}

/// A block 1 wide and 1 tall on 10 x 10 cells of 2 x 2 points (two empty rows above),
/// fixed at its base, on rollers at its sides, under gravity -y.
Model<2> block(std::shared_ptr<const Material> material) {
  Model<2> m(Grid<2>(Vec<2>(0.0, 0.0), Vec<2>(0.1, 0.1), {10, 12}));
  m.materials = {std::move(material)};
  add_regular_points<2>(m.grid, {0, 0}, {10, 10}, 2, [](const Vec<2>&) { return true; }, 0, kRho, m.points);
  support(m);
  m.initialise_state();
  return m;
}

double largest_displacement(const Model<2>& m) {
  double u = 0.0;
  for (int p = 0; p < m.points.size(); ++p)
    u = std::max(u, (m.points.position[p] - m.points.original_position[p]).norm());
  return u;
}

}  // namespace

TEST(Geostatic, G1_AnElasticBlockStartsAtRestUnderItsWeight) {
  const double k0 = kNu / (1.0 - kNu), H = 1.0, scale = kRho * kG * H;
  Model<2> m = block(std::make_shared<LinearElastic>(kE, kNu, kRho));
  ASSERT_EQ(start_geostatic(m, {k0}).expected, "");
  EXPECT_TRUE(m.dead_gravity);
  double start_error = 0.0;
  for (int p = 0; p < m.points.size(); ++p) {
    const double sv = kRho * kG * (H - m.points.position[p][1]);
    const Mat3& s = m.points.stress[p];
    start_error = std::max({start_error, std::abs(s(1, 1) + sv), std::abs(s(0, 0) + k0 * sv),
                            std::abs(s(2, 2) + k0 * sv), std::abs(s(0, 1))});
  }
  EXPECT_LE(start_error, 1e-12 * scale);
  const std::vector<Mat3> start = m.points.stress;

  NewtonSettings s;
  s.load_steps = 4;  // (a gravity ramped with the load factor would lift the block at the first)
  run_quasi_static<2>(m, s);
  double stress_change = 0.0;
  for (int p = 0; p < m.points.size(); ++p) stress_change = std::max(stress_change, (m.points.stress[p] - start[p]).norm());
  // gravity ramped from zero on the same block: the settlement rho g H^2 / (2 E_oed)
  Model<2> ramped = block(std::make_shared<LinearElastic>(kE, kNu, kRho));
  run_quasi_static<2>(ramped, s);
  const double u = largest_displacement(m), u_ramped = largest_displacement(ramped);
  std::cout << "  geostatic start: |u| = " << u << " (gravity ramped: " << u_ramped
            << "), max |d sigma| / rho g H = " << stress_change / scale << "\n";
  EXPECT_LE(u, 1e-3 * u_ramped);
  EXPECT_LE(stress_change, 1e-2 * scale);
}

TEST(Geostatic, G6_AnAxisymmetricCylinderStartsAtRestUnderItsWeight) {
  const double k0 = kNu / (1.0 - kNu), H = 1.0, scale = kRho * kG * H;
  auto cylinder = [] {  // (as the reader makes it: volumes and masses per radian)
    Model<2> m = block(std::make_shared<LinearElastic>(kE, kNu, kRho));
    m.axisymmetric = true;
    for (int p = 0; p < m.points.size(); ++p) {
      const double r = m.points.position[p][0];
      m.points.volume[p] *= r;
      m.points.original_volume[p] *= r;
      m.points.mass[p] *= r;
    }
    return m;
  };
  Model<2> m = cylinder();
  ASSERT_EQ(start_geostatic(m, {k0}).expected, "");
  double start_error = 0.0;
  for (int p = 0; p < m.points.size(); ++p) {
    const double sv = kRho * kG * (H - m.points.position[p][1]);
    const Mat3& s = m.points.stress[p];
    start_error = std::max({start_error, std::abs(s(1, 1) + sv), std::abs(s(0, 0) + k0 * sv),
                            std::abs(s(2, 2) + k0 * sv), std::abs(s(0, 1))});
  }
  EXPECT_LE(start_error, 1e-12 * scale);
  const std::vector<Mat3> start = m.points.stress;
  NewtonSettings s;
  s.load_steps = 4;
  run_quasi_static<2>(m, s);
  double stress_change = 0.0;
  for (int p = 0; p < m.points.size(); ++p) stress_change = std::max(stress_change, (m.points.stress[p] - start[p]).norm());
  Model<2> ramped = cylinder();
  run_quasi_static<2>(ramped, s);
  const double u = largest_displacement(m), u_ramped = largest_displacement(ramped);
  std::cout << "  axisymmetric geostatic start: |u| = " << u << " (gravity ramped: " << u_ramped
            << "), max |d sigma| / rho g H = " << stress_change / scale << "\n";
  EXPECT_LE(u, 1e-3 * u_ramped);
  EXPECT_LE(stress_change, 1e-2 * scale);
}

TEST(Geostatic, G2_ASaturatedColumnStartsHydrostaticAndStaysThere) {
  const int n = 40;
  const double H = 1.0, rho_w = 1000.0, E = 1e7;
  Model<1> m(Grid<1>(Vec<1>(0.0), Vec<1>(H / n), {n + 2}));
  m.materials = {std::make_shared<LinearElastic>(E, 0.0, kRho)};
  add_regular_points<1>(m.grid, {0}, {n}, 2, [](const Vec<1>&) { return true; }, 0, kRho, m.points);
  m.gravity = Vec<1>(-kG);
  m.constraints = {{0, 0, 0.0}};
  m.pore.drainage = PoreSettings::Drainage::Coupled;
  m.pore.fluids = {PoreFluid{1e-6, 2.2e9, 0.4, rho_w}};
  m.pore.constraints = {{n, 0.0}};
  m.pore.gravity = kG;
  m.pore.water_table = H;
  m.time.dt = 1.0;
  m.time.end_time = 1.0;
  m.time.inertia = false;
  m.initialise_state();
  ASSERT_EQ(start_geostatic(m, {1.0}).expected, "");
  const double scale = rho_w * kG * H;
  double p_error = 0.0, s_error = 0.0;
  for (int p = 0; p < m.points.size(); ++p) {
    const double d = H - m.points.position[p][0];
    p_error = std::max(p_error, std::abs(m.points.pore_pressure[p] - rho_w * kG * d));
    s_error = std::max(s_error, std::abs(m.points.stress[p](0, 0) + (kRho - rho_w) * kG * d));
  }
  EXPECT_LE(p_error, 1e-12 * scale);
  EXPECT_LE(s_error, 1e-12 * scale);

  NewtonSettings s;
  run_quasi_static<1>(m, s);
  double settlement = 0.0;
  p_error = 0.0;
  for (int p = 0; p < m.points.size(); ++p) {
    p_error = std::max(p_error, std::abs(m.points.pore_pressure[p] - rho_w * kG * (H - m.points.original_position[p][0])));
    settlement = std::max(settlement, -(m.points.position[p][0] - m.points.original_position[p][0]));
  }
  const double drained = (kRho - rho_w) * kG * H * H / (2.0 * E);  // its buoyant weight on the column
  std::cout << "  saturated column after a step: max |p - p_hydrostatic| / rho_w g H = " << p_error / scale
            << ", settlement / drained = " << settlement / drained << "\n";
  EXPECT_LE(p_error, 1e-6 * scale);
  EXPECT_LE(settlement, 1e-3 * drained);
}

TEST(Geostatic, G3_ModifiedCamClayStartsOnOrInsideItsSurface) {
  for (const double ocr : {1.0, 2.0}) {
    CamClayParameters c{.lambda = 0.2, .kappa = 0.04, .M = 1.2, .e0 = 1.2, .p0 = 100e3, .pc0 = 100e3, .ocr = ocr,
                        .shear_modulus = 3e6};
    const ModifiedCamClay law(c, kRho);
    const double sv = 60e3, k0 = 0.6;
    const Mat3 sigma = Eigen::Vector3d(-k0 * sv, -sv, -k0 * sv).asDiagonal();
    std::vector<double> state(law.state_size()), next(law.state_size());
    ASSERT_TRUE(law.start_from_stress(sigma, state.data()));
    MaterialResponse r;
    law.update(Mat3::Identity(), state.data(), next.data(), r);
    EXPECT_LE((r.stress - sigma).norm(), 1e-10 * sv) << "OCR " << ocr;
    const double P = (1.0 + 2.0 * k0) * sv / 3.0, q = (1.0 - k0) * sv;
    const double Pc = law.preconsolidation(state[PlasticLaw::kKappa]);
    EXPECT_NEAR(Pc, ocr * (P + q * q / (c.M * c.M * P)), 1e-12 * Pc);
    const double f = q * q / (c.M * c.M) + P * (P - Pc);
    if (ocr == 1.0)
      EXPECT_LE(std::abs(f), 1e-12 * P * P);
    else
      EXPECT_LT(f, -0.1 * P * P);
  }
}

TEST(Geostatic, G4_AStressOutsideTheYieldSurfaceIsRefused) {
  MohrCoulombParameters mc;
  mc.cohesion = 1e3;
  mc.friction_angle = 30.0;
  mc.dilation_angle = 0.0;
  Model<2> m = block(std::make_shared<MohrCoulomb>(IsotropicElasticity(kE, kNu), kRho, mc));
  const GeostaticProblem problem = start_geostatic(m, {0.1});
  std::cout << "  refused: " << problem.key << ": " << problem.expected << "\n";
  EXPECT_EQ(problem.key, "initial_stress.k0");
  EXPECT_NE(problem.expected.find("inside the yield surface"), std::string::npos);
  EXPECT_NE(problem.expected.find("mohr-coulomb"), std::string::npos);
  EXPECT_TRUE(start_geostatic(m, {0.5}).empty());  // 1 - sin 30 deg: inside
}

namespace {

/// G5's layer: 6 x 4 on cells of 0.5 (2 x 2 points; one empty row above), rollers at its
/// sides, a rough base, the load q on the top points with x < 1 (B / 2 = 1); the top cell
/// row an elastic crust that spreads the load (the clay at the surface has no strength).
Model<2> clay_layer(bool coupled) {
  Model<2> m(Grid<2>(Vec<2>(0.0, 0.0), Vec<2>(0.5, 0.5), {12, 9}));
  const CamClayParameters c{.lambda = 0.2, .kappa = 0.04, .M = 1.0, .e0 = 1.5, .p0 = 20e3, .pc0 = 20e3, .ocr = 4.0,
                            .shear_modulus = 3e5};
  // A light pore fluid (rho_w = 1, k scaled to keep k / gamma_w): with water, the points that
  // settle by d below the fixed water table gain gamma_w d of buoyancy, which the drained
  // run at its buoyant weight does not see (1.2 % of the settlement here).
  const double rho_w = 1.0, rho = coupled ? 1800.0 : 1800.0 - rho_w;
  m.materials = {std::make_shared<ModifiedCamClay>(c, rho), std::make_shared<Hencky>(2e6, 0.3, rho)};
  add_regular_points<2>(m.grid, {0, 0}, {12, 7}, 2, [](const Vec<2>&) { return true; }, 0, rho, m.points);
  add_regular_points<2>(m.grid, {0, 7}, {12, 8}, 2, [](const Vec<2>&) { return true; }, 1, rho, m.points);
  for (int p = 0; p < m.points.size(); ++p)
    if (m.points.position[p][1] > 3.8 && m.points.position[p][0] < 1.0) m.points.force[p] = Vec<2>(0.0, -5e3 * 0.25);
  support(m);
  if (coupled) {
    m.pore.drainage = PoreSettings::Drainage::Coupled;
    m.pore.fluids = {PoreFluid{1e-9, 2.2e9, 0.6, rho_w}, PoreFluid{1e-8, 2.2e9, 0.5, rho_w}};
    for (int i = 0; i <= 12; ++i) m.pore.constraints.push_back({m.grid.node_index({i, 8}), 0.0});
    m.pore.gravity = kG;
    m.pore.water_table = 4.0;
    m.time.dt = 2e3;
    m.time.ramp_time = 2e3;
    m.time.end_time = 1e6;
    m.time.inertia = false;
  }
  m.initialise_state();
  EXPECT_EQ(start_geostatic(m, {0.6}).expected, "");
  return m;
}

/// The settlement of the top point nearest the load's centre line.
double centre_settlement(const Model<2>& m) {
  int top = 0;
  for (int p = 0; p < m.points.size(); ++p)
    if (m.points.original_position[p][1] > m.points.original_position[top][1] ||
        (m.points.original_position[p][1] == m.points.original_position[top][1] &&
         m.points.original_position[p][0] < m.points.original_position[top][0]))
      top = p;
  return m.points.original_position[top][1] - m.points.position[top][1];
}

}  // namespace

TEST(Geostatic, G5_AStripLoadOnClayConsolidatesToTheDrainedSettlement) {
  Model<2> drained = clay_layer(false);
  NewtonSettings s;
  s.load_steps = 4;
  run_quasi_static<2>(drained, s);
  const double s_drained = centre_settlement(drained);

  Model<2> m = clay_layer(true);
  std::vector<double> kappa_start(m.points.size());
  for (int p = 0; p < m.points.size(); ++p) kappa_start[p] = m.points.state_of(p)[PlasticLaw::kKappa];
  double s_first = -1.0;
  run_quasi_static<2>(m, NewtonSettings{}, [&](const Model<2>& mm, const StepInfo&) {
    if (s_first < 0.0) s_first = centre_settlement(mm);
  });
  const double s_end = centre_settlement(m);
  Model<2> undrained = clay_layer(true);  // k = 0: the load's step without flow
  for (auto& f : undrained.pore.fluids) f.conductivity = 0.0;
  undrained.time.end_time = undrained.time.dt;
  run_quasi_static<2>(undrained, NewtonSettings{});
  const double s_undrained = centre_settlement(undrained);
  double yielded = 0.0;
  for (int p = 0; p < m.points.size(); ++p)
    yielded = std::max(yielded, std::abs(m.points.state_of(p)[PlasticLaw::kKappa] - kappa_start[p]));
  std::cout << "  strip load on clay: settlement undrained (k = 0) " << s_undrained << ", after the first step "
            << s_first << ", at the end " << s_end << ", drained " << s_drained << " (largest change of eps_v^p "
            << yielded << ")\n";
  EXPECT_LE(yielded, 1e-12);  // (the premise: elastic, so both runs end at one equilibrium)
  EXPECT_LT(s_undrained, s_first);
  EXPECT_LT(s_first, s_end);
  EXPECT_NEAR(s_end, s_drained, 1e-2 * s_drained);
}
