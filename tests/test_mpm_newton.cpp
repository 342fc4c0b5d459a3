// Requirements on the Newton load stepping:
//  R1 the consistent tangent gives quadratic convergence on a finite-strain problem
//     (the column in one load step: the residual history is printed and the rate checked);
//  R2 a case with no load leaves every point where it was;
//  R3 a step that fails is cut (halved) and retried; when the cuts are exhausted the run
//     stops with SolverError and the points keep the last converged state;
//  R4 points that leave the grid stop the run with their ids listed;
//  R5 a residual stalled at round-off a few times above the estimated floor counts as
//     converged (the biaxial test on a six times finer grid, at 1/2560 of its load, could
//     not start: 8.5e4 dof, 1.4e-7 relative for 25 iterations, every cut).
//  R6 a load step whose sparsity pattern is the previous step's keeps the direct
//     solver's symbolic analysis, and the run's answer is the same to the bit as with an
//     analysis in every step.
//  R7 a load step whose pattern has changed takes the previous step's ordering, carried
//     through the grid nodes (NewtonSettings::reuse_ordering): the footing, whose points
//     move through the grid, computes fewer orderings than analyses, and its answer is
//     the one with an ordering computed at every analysis, to round-off.
//  R8 an iterate at which a material update fails (NaN stress: F-bar's scaled increment at
//     a point squeezed to dJ = 5e-9 did so in the biaxial example) is never taken as
//     converged: it is backtracked like an inverted point, and a step that finds no finite
//     iterate is cut; when the cuts are exhausted the run stops with SolverError saying so
//     and the points keep the last converged state. (A NaN internal force gave the
//     relative residual 0 and was accepted; the run went on with NaN states.)
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <memory>

#include <fmt/format.h>

#include "MpmTestUtil.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/materials/Hencky.hpp"
#include "gradmpm/materials/LinearElastic.hpp"

using namespace gradmpm;
using namespace gradmpm::test;

TEST(MpmNewton, QuadraticConvergenceOnAFiniteStrainStep) {
  for (BasisKind b : {BasisKind::MPM, BasisKind::CPGIMP}) {
    Model<2> m = make_column<2>(8, b);
    NewtonSettings s;
    s.load_steps = 1;  // the whole self-weight in one step: 31 % compression
    s.tolerance = 1e-13;
    std::vector<double> r;
    run_quasi_static<2>(m, s, [&](const Model<2>&, const StepInfo& info) { r = info.residuals; });
    std::cout << to_string(b) << " residuals:";
    for (double x : r) std::cout << " " << x;
    std::cout << "\n";
    ASSERT_GE(r.size(), 4u);
    int checked = 0;
    for (std::size_t k = 1; k + 1 < r.size(); ++k)
      if (r[k] < 1e-2 && r[k + 1] > 1e-14) {  // asymptotic range, above round-off
        const double rate = std::log(r[k + 1]) / std::log(r[k]);
        std::cout << "  log r_{k+1} / log r_k = " << rate << "\n";
        EXPECT_GT(rate, 1.8);
        ++checked;
      }
    EXPECT_GE(checked, 1);
    EXPECT_LE(r.size(), 8u);
  }
}

TEST(MpmNewton, NoLoadLeavesPointsInPlace) {
  Model<2> m = make_column<2>(4, BasisKind::UGIMP);
  m.gravity.setZero();
  NewtonSettings s;
  s.load_steps = 5;
  const auto summary = run_quasi_static<2>(m, s);
  EXPECT_EQ(summary.total_iterations, 0);
  for (int p = 0; p < m.points.size(); ++p) {
    EXPECT_EQ(m.points.position[p], m.points.original_position[p]);
    EXPECT_EQ(m.points.stress[p].norm(), 0.0);
  }
}

TEST(MpmNewton, FailingStepsAreCutAndRetried) {
  Model<2> m = make_column<2>(8, BasisKind::CPGIMP);
  NewtonSettings s;
  s.load_steps = 1;
  s.max_iterations = 3;  // too few for the whole load at once
  const auto summary = run_quasi_static<2>(m, s);
  EXPECT_GT(summary.cuts, 0);
  const ColumnErrors cut = column_errors(m);
  Model<2> ref = make_column<2>(8, BasisKind::CPGIMP);
  NewtonSettings sr;
  sr.load_steps = 8;
  run_quasi_static<2>(ref, sr);
  std::cout << "cuts " << summary.cuts << " steps " << summary.steps << " stress error " << cut.stress
            << " (8 steps: " << column_errors(ref).stress << ")\n";
  EXPECT_LT(cut.stress, 0.05);
}

TEST(MpmNewton, ExhaustedCutsStopWithTheLastConvergedState) {
  Model<2> m = make_column<2>(8, BasisKind::MPM);
  NewtonSettings s;
  s.load_steps = 4;
  s.max_iterations = 1;
  s.max_cuts = 1;
  const auto before = m.points.position;
  try {
    run_quasi_static<2>(m, s);
    FAIL() << "expected SolverError";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("load step 1 failed"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("after 1 cut(s)"), std::string::npos) << e.what();
  }
  EXPECT_EQ(m.points.position, before);
}

namespace {
/// A law whose update fails (NaN stress) wherever its strain is not zero: Hencky's
/// otherwise.
class FailingUpdate final : public Material {
 public:
  explicit FailingUpdate(std::shared_ptr<const Material> inner)
      : Material(inner->elasticity(), inner->density()), inner_(std::move(inner)) {}
  std::string model() const override { return "failing-update"; }
  bool finite_strain() const override { return inner_->finite_strain(); }
  const std::vector<StateVariable>& state_variables() const override { return inner_->state_variables(); }
  void update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const override {
    inner_->update(dF, state_n, state, out);
    if (inner_->elastic_strain(state).norm() > 0.0) out.stress.setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  void tangent(const MaterialResponse& r, int dim, Mat9& A) const override { inner_->tangent(r, dim, A); }
  Mat3 elastic_strain(const double* state) const override { return inner_->elastic_strain(state); }

 private:
  std::shared_ptr<const Material> inner_;
};
}  // namespace

TEST(MpmNewton, AnIterateWithAFailedMaterialUpdateIsNeverTakenAsConverged) {  // R8
  // No external force: the column's top is pushed down (as the biaxial example's platen),
  // so that the forces' scale is the internal force's alone.
  Model<2> m = make_column<2>(8, BasisKind::CPGIMP);
  m.materials[0] = std::make_shared<FailingUpdate>(m.materials[0]);
  m.gravity.setZero();
  for (int node = 0; node < m.grid.num_nodes(); ++node)
    if (m.grid.node_ijk(node)[1] == m.grid.cells()[1]) m.constraints.push_back({node, 1, -0.01});
  NewtonSettings s;
  s.load_steps = 2;
  s.max_cuts = 2;
  const auto before = m.points.position;
  StepInfo last;
  try {
    run_quasi_static<2>(m, s, [&](const Model<2>&, const StepInfo& info) { last = info; });
    FAIL() << "expected SolverError; the last step's residuals end with " << last.residuals.back();
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("load step 1 failed"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("internal force is not finite"), std::string::npos) << e.what();
  }
  EXPECT_EQ(m.points.position, before);
  for (int p = 0; p < m.points.size(); ++p) EXPECT_TRUE(m.points.stress[p].allFinite());
}

TEST(MpmNewton, PointsLeavingTheGridAreListed) {
  // A block pushed down through the bottom of its grid by a prescribed displacement.
  Model<1> m(Grid<1>(Vec<1>(0.0), Vec<1>(1.0), {4}));
  m.materials.push_back(std::make_shared<LinearElastic>(100.0, 0.0, 1.0));
  add_regular_points<1>(
      m.grid, {0}, {4}, 1, [](const Vec<1>&) { return true; }, 0, 1.0, m.points);
  for (int node = 0; node < 5; ++node) m.constraints.push_back({node, 0, -2.0});  // rigid shift by -2
  NewtonSettings s;
  s.load_steps = 2;
  try {
    run_quasi_static<1>(m, s);
    FAIL() << "expected SolverError";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("load step 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("outside the grid (ids): 0"), std::string::npos) << e.what();
  }
  EXPECT_NEAR(m.points.position[0][0], -0.5, 1e-14) << "the converged first step is kept";
}

TEST(MpmNewton, AResidualStalledAtRoundOffCountsAsConverged) {  // R5
  const double h = 1.0 / (24.0 * 6);
  CaseFile cf =
      CaseFile::load(std::string(GRADMPM_SOURCE_DIR) + "/examples/biaxial_2d.toml",
                     {fmt::format("grid.origin=[-0.25,{}]", -2 * h), fmt::format("grid.cell_size={}", h),
                      fmt::format("grid.cells=[{},{}]", 36 * 6, 52 * 6 + 2), "load_steps.count=2560",
                      "rigid_boxes[0].displacement=[0.0,-0.045]", "nonlinear_solver.max_cuts=0", "output.vtk_every=0"});
  cf.remove_section("regularisation");  // the Newton solve alone
  MpmCase<2> c = read_mpm_case<2>(cf);
  struct Stop {};
  StepInfo first;
  try {
    run_quasi_static<2>(c.model, c.newton, [&](const Model<2>&, const StepInfo& info) {
      first = info;
      throw Stop{};
    });
  } catch (const Stop&) {
  }
  ASSERT_EQ(first.step, 1) << "the first step did not converge";
  EXPECT_EQ(first.cuts, 0);
  EXPECT_LE(first.phases.iterations, 8);
  std::printf("first step: %d iterations, last relative residual %.2e (tolerance %.0e)\n", first.phases.iterations,
              first.residuals.back(), c.newton.tolerance);
}

TEST(MpmNewton, AnUnchangedPatternKeepsTheAnalysisAndTheAnswer) {  // R6
  auto run = [](bool reuse, int& analyses) {
    Model<2> m = make_column<2>(8, BasisKind::CPGIMP);
    NewtonSettings s;
    s.load_steps = 20;
    s.reuse_analysis = reuse;
    s.reuse_ordering = false;  // (R7: to round-off only)
    analyses = 0;
    run_quasi_static<2>(m, s, [&](const Model<2>&, const StepInfo& info) { analyses += info.phases.analyses; });
    return m;
  };
  int kept = 0, every = 0;
  const Model<2> a = run(true, kept), b = run(false, every);
  std::cout << "symbolic analyses in 20 steps: " << kept << " kept across steps, " << every << " without\n";
  EXPECT_EQ(every, 20);
  EXPECT_LT(kept, every);
  EXPECT_GT(kept, 1);  // the column's points do cross cells: some steps need a new one
  for (int p = 0; p < a.points.size(); ++p) {
    EXPECT_EQ(a.points.position[p], b.points.position[p]) << "point " << p;
    EXPECT_EQ(a.points.stress[p], b.points.stress[p]) << "point " << p;
  }
}

TEST(MpmNewton, AChangedPatternTakesThePreviousStepsOrdering) {  // R7
  struct Run {
    Model<2> model;
    int analyses = 0, orderings = 0;
  };
  auto run = [](bool reuse) {
    CaseFile cf = CaseFile::load(std::string(GRADMPM_SOURCE_DIR) + "/examples/footing_2d.toml", {"output.vtk_every=0"});
    MpmCase<2> c = read_mpm_case<2>(cf);
    c.newton.reuse_ordering = reuse;
    Run r{std::move(c.model)};
    run_quasi_static<2>(r.model, c.newton, [&](const Model<2>&, const StepInfo& info) {
      r.analyses += info.phases.analyses;
      r.orderings += info.phases.orderings;
    });
    return r;
  };
  const Run taken = run(true), fresh = run(false);
  std::cout << "footing, 40 steps: " << taken.analyses << " analyses with " << taken.orderings
            << " orderings computed (the others taken); " << fresh.analyses << " analyses, each ordered afresh\n";
  EXPECT_EQ(fresh.orderings, fresh.analyses);
  EXPECT_GT(fresh.analyses, 10) << "the points must cross cells for this test to mean anything";
  EXPECT_LT(taken.orderings, taken.analyses / 2);
  double width = 0.0, scale = 0.0;
  for (int p = 0; p < fresh.model.points.size(); ++p) {
    width = std::max(width, fresh.model.points.position[p].norm());
    scale = std::max(scale, fresh.model.points.stress[p].norm());
  }
  double dx = 0.0, ds = 0.0;
  for (int p = 0; p < taken.model.points.size(); ++p) {
    dx = std::max(dx, (taken.model.points.position[p] - fresh.model.points.position[p]).norm());
    ds = std::max(ds, (taken.model.points.stress[p] - fresh.model.points.stress[p]).norm());
  }
  EXPECT_LT(dx, 1e-10 * width);
  EXPECT_LT(ds, 1e-8 * scale);
  std::cout << "largest differences: position " << dx / width << ", stress " << ds / scale << " (relative)\n";
}
