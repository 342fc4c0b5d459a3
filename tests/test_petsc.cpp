// Requirements on the PETSc linear solver (linear_solver.type = "petsc"):
//  P1 its defaults (CG with GAMG for symmetric matrices; MUMPS's LU for general ones, or
//     GMRES with GAMG when -ksp_type is named) give CHOLMOD's and UMFPACK's solutions to
//     1e-8;
//  P2 a Krylov solve that does not converge is a SolverError naming the method, the
//     iterations and the residual reached;
//  P3 linear_solver.options reach PETSc's options database (any KSP or PC can be chosen:
//     here MUMPS's direct LU and hypre's BoomerAMG), and bad ones (an unknown type, an
//     option PETSc does not use) are refused when the case is read, exit code 2, naming
//     the key;
//  P4 on MPM runs (a 2D footing, a 3D block under self-weight, an elasto-plastic Tresca
//     footing) it gives CHOLMOD's positions and stresses to 1e-8 relative, and the inexact
//     Newton (Eisenstat-Walker forcing) needs at most 10 % more Newton iterations than the
//     exact one at the default tolerance (the quadratic rate is kept to the end: the
//     elasto-plastic footing's 8 steps took 49 exact and 49 or 50 inexact, as round-off in
//     the assembly changed; a loose first solve costs an iteration now and then);
//  P5 the gradient step's Helmholtz systems use it too and give CHOLMOD's enriched
//     fields to 1e-8;
//  P7 the coupled u-p step's systems (3 unknowns per node in 2D, non-symmetric) are solved
//     by the fieldsplit Schur preconditioner given as options (the displacements by GAMG,
//     the pressure's Schur complement by Jacobi on its selfp approximation), to the direct
//     solver's pore pressures and positions to 1e-8 (Mandel's example, 5 steps);
//  P6 a scalar system (no rigid-body modes) with rows of very different scales (nodes a
//     point barely reaches) is solved as fast as the same system well scaled: CG with
//     GAMG is diagonally scaled, and needs at most 5 iterations more.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "CaseTextUtil.hpp"
#include "CliTestUtil.hpp"
#include "MpmTestUtil.hpp"
#include "SolverTestUtil.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

using namespace gradmpm;
using gradmpm::test::slurp;
namespace fs = std::filesystem;

namespace {

LinearSolverSettings petsc(const std::string& options = "") {
  LinearSolverSettings s;
  s.type = "petsc";
  s.general = "petsc";
  s.options = options;
  return s;
}

using test::laplacian_2d;

/// Points' positions and stresses of two runs: the largest difference of each, relative
/// to the largest displacement and the largest stress component.
template <int dim>
std::pair<double, double> difference(const Model<dim>& a, const Model<dim>& b) {
  double dx = 0.0, u = 0.0, ds = 0.0, s = 0.0;
  for (int p = 0; p < a.points.size(); ++p) {
    dx = std::max(dx, (a.points.position[p] - b.points.position[p]).norm());
    u = std::max(u, (a.points.position[p] - a.points.original_position[p]).norm());
    ds = std::max(ds, (a.points.stress[p] - b.points.stress[p]).cwiseAbs().maxCoeff());
    s = std::max(s, a.points.stress[p].cwiseAbs().maxCoeff());
  }
  return {dx / u, ds / s};
}

/// PETSc's run `b` gives CHOLMOD's run `a`: positions and stresses to 1e-8 relative.
template <int dim>
void expect_same_answer(const char* what, const Model<dim>& a, const Model<dim>& b) {
  const auto [dx, ds] = difference(a, b);
  std::printf("%s: petsc - cholmod: positions %.2e, stresses %.2e\n", what, dx, ds);
  EXPECT_LT(dx, 1e-8) << what;
  EXPECT_LT(ds, 1e-8) << what;
}

template <int dim>
struct Outcome {
  Model<dim> model;
  RunSummary summary;
};

struct Stop {};

/// Runs the case, to its end or to the end of load step `steps`.
template <int dim>
Outcome<dim> run(CaseFile cf, int steps = 0) {
  MpmCase<dim> c = read_mpm_case<dim>(cf);
  Outcome<dim> r{std::move(c.model), {}};
  try {
    r.summary = run_quasi_static<dim>(r.model, c.newton, [&](const Model<dim>&, const StepInfo& info) {
      r.summary.total_iterations += info.phases.iterations;
      if (info.step == steps) throw Stop{};
    });
  } catch (const Stop&) {
  }
  return r;
}

const std::string kPetsc = "linear_solver.type=\"petsc\"";

/// A block 1 x 1 x 1 of Hencky soil (nu = 0.3) under self-weight large enough to squash it
/// by a tenth, n cells per side (cpGIMP), base fixed, the four sides on rollers.
std::string block_3d(int n) {
  const double h = 1.0 / n;
  std::string t = fmt::format(R"(
[grid]
origin = [{0}, {0}, {0}]
cell_size = {1}
cells = [{2}, {2}, {2}]
[basis]
type = "cpgimp"
[materials.soil]
model = "hencky"
young = 100.0
poisson = 0.3
density = 1.0
[[bodies]]
material = "soil"
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
[loads]
gravity = [0.0, 0.0, -20.0]
[[constraints]]
min = [{0}, {0}, {0}]
max = [2.0, 2.0, 0.0]
fix = ["x", "y", "z"]
[load_steps]
count = 3
[output]
vtk_every = 0
)",
                              -h, h, n + 2);
  for (const char* side : {"min = [{0}, {0}, {0}]\nmax = [0.0, 2.0, 2.0]\nfix = [\"x\"]",
                           "min = [1.0, {0}, {0}]\nmax = [2.0, 2.0, 2.0]\nfix = [\"x\"]",
                           "min = [{0}, {0}, {0}]\nmax = [2.0, 0.0, 2.0]\nfix = [\"y\"]",
                           "min = [{0}, 1.0, {0}]\nmax = [2.0, 2.0, 2.0]\nfix = [\"y\"]"})
    t += "[[constraints]]\n" + fmt::format(fmt::runtime(side), -h) + "\n";
  return t;
}

fs::path example(const char* name) { return fs::path(GRADMPM_SOURCE_DIR) / "examples" / name; }

}  // namespace

TEST(Petsc, IsRegisteredAndSolvesGeneralMatrices) {
  const LinearSolverInfo* info = LinearSolverRegistry::instance().find("petsc");
  ASSERT_NE(info, nullptr);
  EXPECT_TRUE(info->general);
  EXPECT_TRUE(info->takes_options);
}

TEST(Petsc, DefaultKrylovSolversGiveTheDirectSolutions) {  // P1
  const SparseMatrix A = laplacian_2d(40);
  const Vector b = Vector::LinSpaced(A.rows(), -1.0, 2.0);
  const auto chol = make_linear_solver({}), cg = make_linear_solver(petsc());
  EXPECT_FALSE(cg->general());  // CG: the symmetric systems
  EXPECT_TRUE(cg->iterative());
  chol->compute(A);
  cg->set_relative_tolerance(1e-12);
  cg->compute(A);
  const Vector x = chol->solve(b);
  EXPECT_LT((cg->solve(b) - x).norm(), 1e-8 * x.norm());
  EXPECT_GT(cg->iterations(), 0);
  // New values on the same pattern (the next Newton iteration): refactorise and solve again.
  const SparseMatrix A2 = 2.0 * A;
  cg->factorize(A2);
  EXPECT_LT((cg->solve(b) - 0.5 * x).norm(), 1e-8 * x.norm());

  const SparseMatrix N = laplacian_2d(40, 0.3);
  LinearSolverSettings lu;
  lu.type = "umfpack";
  const auto umf = make_linear_solver(lu, MatrixKind::General),
             mumps = make_linear_solver(petsc(), MatrixKind::General),
             gmres = make_linear_solver(petsc("-ksp_type gmres"), MatrixKind::General);
  umf->compute(N);
  const Vector y = umf->solve(b);
  for (LinearSolver* s : {mumps.get(), gmres.get()}) {
    EXPECT_TRUE(s->general());
    s->set_relative_tolerance(1e-12);
    s->compute(N);
    EXPECT_LT((s->solve(b) - y).norm(), 1e-8 * y.norm());
  }
  EXPECT_EQ(mumps->iterations(), 1);  // one application of the LU factors
  EXPECT_GT(gmres->iterations(), 1);
}

TEST(Petsc, BadlyScaledRowsCostNoMoreIterations) {  // P6
  const SparseMatrix A = laplacian_2d(60);
  Vector d = Vector::Ones(A.rows());
  for (Eigen::Index i = 0; i < d.size(); i += 7) d[i] = 1e-4;  // rows 1e-8 of the others
  const SparseMatrix B = d.asDiagonal() * A * d.asDiagonal();
  const Vector b = Vector::LinSpaced(A.rows(), -1.0, 2.0);
  const auto chol = make_linear_solver({});
  long its[2];
  for (int k = 0; k < 2; ++k) {
    const SparseMatrix& M = k == 0 ? A : B;
    const auto cg = make_linear_solver(petsc());
    chol->compute(M);
    cg->set_relative_tolerance(1e-12);
    cg->compute(M);
    const Vector x = chol->solve(b);
    EXPECT_LT((cg->solve(b) - x).norm(), 1e-8 * x.norm()) << (k == 0 ? "well scaled" : "badly scaled");
    its[k] = cg->iterations();
  }
  std::printf("CG + GAMG iterations: %ld well scaled, %ld badly scaled\n", its[0], its[1]);
  EXPECT_LE(its[1], its[0] + 5);
}

TEST(Petsc, AKrylovFailureSaysHowFarItGot) {  // P2
  const SparseMatrix A = laplacian_2d(40);
  const auto s = make_linear_solver(petsc("-ksp_max_it 2 -ksp_rtol 1e-14 -pc_type jacobi"));
  s->compute(A);
  try {
    s->solve(Vector(Vector::Ones(A.rows())));
    FAIL() << "expected SolverError";
  } catch (const SolverError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("PETSc cg with jacobi did not converge (DIVERGED_ITS)"), std::string::npos) << m;
    EXPECT_NE(m.find("after 2 iterations"), std::string::npos) << m;
  }
}

TEST(Petsc, OptionsChooseAnyKspAndPcAndBadOnesAreRefusedWithTheKey) {  // P3
  const std::string text = slurp(example("column_2d.toml"));
  const std::vector<std::string> base = {"output.check=", "load_steps.count=3", "nonlinear_solver.tolerance=1e-12"};
  const Outcome<2> ref = run<2>(CaseFile::parse(text, "column_2d.toml", base));
  for (const char* options :
       {"-ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps", "-pc_type hypre -pc_hypre_type boomeramg"}) {
    std::vector<std::string> sets = base;
    sets.push_back(kPetsc);
    sets.push_back(fmt::format("linear_solver.options=\"{}\"", options));
    const Outcome<2> r = run<2>(CaseFile::parse(text, "column_2d.toml", sets));
    expect_same_answer(options, ref.model, r.model);
  }
  const auto refused = [&](const std::string& options) {
    return test::read_error<2>(
        CaseFile::parse(text, "column_2d.toml", {kPetsc, fmt::format("linear_solver.options=\"{}\"", options)}));
  };
  const std::string unknown = refused("-pc_type nonsense");
  EXPECT_NE(unknown.find("linear_solver.options (from --set): expected options PETSc accepts"), std::string::npos)
      << unknown;
  EXPECT_NE(unknown.find("nonsense"), std::string::npos) << unknown;
  const std::string misspelt = refused("-pc_type gamg -pc_gamg_threshhold 0.01");
  EXPECT_NE(misspelt.find("it did not use -pc_gamg_threshhold"), std::string::npos) << misspelt;
  const auto named = misspelt.find("did not use");
  ASSERT_NE(named, std::string::npos) << misspelt;
  EXPECT_EQ(misspelt.substr(named, misspelt.find(':', named) - named), "did not use -pc_gamg_threshhold")
      << "only the unused option is named";
}

void expect_few_more_iterations(const char* name, const RunSummary& inexact, const RunSummary& exact) {
  fmt::print("{}: {} Newton iterations inexact, {} exact\n", name, inexact.total_iterations, exact.total_iterations);
  EXPECT_LE(inexact.total_iterations, 1.1 * exact.total_iterations) << name;
}

TEST(Petsc, MpmRunsGiveCholmodsAnswer) {  // P4
  const std::vector<std::string> tight = {"nonlinear_solver.tolerance=1e-12", "output.vtk_every=0"};
  auto with_petsc = [](std::vector<std::string> sets) {
    sets.push_back(kPetsc);
    return sets;
  };
  {  // 2D: the strip footing (uGIMP, 10 of its 40 load steps)
    const Outcome<2> a = run<2>(CaseFile::load(example("footing_2d.toml"), tight), 10);
    const Outcome<2> b = run<2>(CaseFile::load(example("footing_2d.toml"), with_petsc(tight)), 10);
    expect_same_answer("footing_2d", a.model, b.model);
  }
  {  // 3D: a block under self-weight, block size 3 and the six rigid-body modes
    const std::string text = block_3d(6);
    const Outcome<3> a = run<3>(CaseFile::parse(text, "block_3d.toml", tight));
    const Outcome<3> b = run<3>(CaseFile::parse(text, "block_3d.toml", with_petsc(tight)));
    expect_same_answer("block_3d", a.model, b.model);
    // At the default tolerance the inexact Newton needs at most 10 % more iterations.
    const Outcome<3> exact = run<3>(CaseFile::parse(text, "block_3d.toml", {}));
    const Outcome<3> inexact = run<3>(CaseFile::parse(text, "block_3d.toml", {kPetsc}));
    expect_few_more_iterations("block_3d", inexact.summary, exact.summary);
  }
  {  // elasto-plastic: the Tresca footing, plastic under the footing
    const Outcome<2> a = run<2>(CaseFile::load(example("footing_tresca_2d.toml"), tight), 8);
    const Outcome<2> b = run<2>(CaseFile::load(example("footing_tresca_2d.toml"), with_petsc(tight)), 8);
    expect_same_answer("footing_tresca_2d", a.model, b.model);
    const Outcome<2> exact = run<2>(CaseFile::load(example("footing_tresca_2d.toml"), {}), 8);
    const Outcome<2> inexact = run<2>(CaseFile::load(example("footing_tresca_2d.toml"), {kPetsc}), 8);
    expect_few_more_iterations("footing_tresca_2d", inexact.summary, exact.summary);
  }
}

TEST(Petsc, FieldsplitSolvesTheCoupledPorePressureStep) {  // P7
  const std::vector<std::string> tight = {"nonlinear_solver.tolerance=1e-12", "output.vtk_every=0"};
  std::vector<std::string> fieldsplit = tight;
  fieldsplit.push_back(kPetsc);
  fieldsplit.push_back(
      "linear_solver.options=\"-ksp_type fgmres -pc_type fieldsplit -pc_fieldsplit_block_size 3 "
      "-pc_fieldsplit_0_fields 0,1 -pc_fieldsplit_1_fields 2 -pc_fieldsplit_type schur "
      "-pc_fieldsplit_schur_fact_type full -pc_fieldsplit_schur_precondition selfp -fieldsplit_0_ksp_type preonly "
      "-fieldsplit_0_pc_type gamg -fieldsplit_1_ksp_type preonly -fieldsplit_1_pc_type jacobi\"");
  const Outcome<2> a = run<2>(CaseFile::load(example("mandel_2d.toml"), tight), 5);
  const Outcome<2> b = run<2>(CaseFile::load(example("mandel_2d.toml"), fieldsplit), 5);
  expect_same_answer("mandel_2d", a.model, b.model);
  double scale = 0.0, diff = 0.0;
  for (int p = 0; p < a.model.points.size(); ++p) {
    scale = std::max(scale, std::abs(a.model.points.pore_pressure[p]));
    diff = std::max(diff, std::abs(a.model.points.pore_pressure[p] - b.model.points.pore_pressure[p]));
  }
  std::printf("mandel_2d: p, fieldsplit - direct %.2e of %.2e\n", diff, scale);
  EXPECT_LT(diff, 1e-8 * scale);
}

TEST(Petsc, GradientStepUsesItAndGivesCholmodsFields) {  // P5
  // The bi-material plate of test_mpm_gradient_2d, e-RA at the end and u-RA (Dirichlet nodes).
  const std::string plate = test::bimaterial_plate(1.0 / 32, 0.1);
  for (const char* variant : {"e-RA", "u-RA"}) {
    std::vector<EnrichedFields<2>> fields;
    for (const bool use_petsc : {false, true}) {
      std::vector<std::string> sets = {fmt::format("gradient.variant=\"{}\"", variant),
                                       "nonlinear_solver.tolerance=1e-12"};
      if (use_petsc) sets.push_back(kPetsc);
      CaseFile cf = CaseFile::parse(plate, "plate.toml", sets);
      MpmCase<2> c = read_mpm_case<2>(cf);
      EXPECT_EQ(c.gradient.linear_solver.type, use_petsc ? "petsc" : "cholmod");
      run_quasi_static<2>(c.model, c.newton);
      fields.push_back(smooth_total<2>(c.model, c.gradient));
    }
    double scale = 0.0, diff = 0.0;
    for (std::size_t p = 0; p < fields[0].strain.size(); ++p) {
      scale = std::max(scale, fields[0].strain[p].cwiseAbs().maxCoeff());
      diff = std::max(diff, (fields[0].strain[p] - fields[1].strain[p]).cwiseAbs().maxCoeff());
    }
    std::printf("%s: enriched strain petsc - cholmod %.2e of %.2e\n", variant, diff, scale);
    EXPECT_LT(diff, 1e-8 * scale) << variant;
  }
}

using PetscCli = test::ScratchDirTest;

TEST_F(PetscCli, BadOptionsExitWithCodeTwoNamingTheKey) {  // P3, from the command line
  const auto r = run_gradmpm(fmt::format(
      "run {} --out {} --set 'linear_solver.type=\"petsc\"' --set 'linear_solver.options=\"-ksp_type nonsense\"'",
      example("column_2d.toml").string(), (dir / "out").string()));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("linear_solver.options"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nonsense"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "points_final.csv"));
}
