// Requirements on extending gradmpm (the recipes of docs/architecture.md), each proved by
// doing it once here, with nothing outside this file changed:
//  R1 "add a material": a law defined only in this test joins MaterialRegistry with one
//     call, declares and reads its own key (with its default and range, and a misspelt
//     key refused with the law's keys listed), and runs through a case file;
//  R2 its state variables reach points_final.csv and the VTU files by name, after the
//     existing columns, with the values the law computed;
//  R3 its non-symmetric tangent is solved as such (linear_solver.general): the linear
//     problem converges in one Newton iteration to the closed form; had it been
//     symmetrised (the law claiming a symmetric tangent, so CHOLMOD reads one triangle)
//     Newton would not converge in one;
//  R4 "add a linear solver": a solver defined only here is chosen by linear_solver.type
//     in a case file, serves every Newton iteration, gives CHOLMOD's answer, and is told
//     what an algebraic multigrid needs (block size dim, the active nodes' coordinates);
//     options reach a solver that takes them and are refused for one that does not;
//  R5 "add a post-step stage": a stage defined only here runs once after every converged
//     load step, sees the committed state, and runs before the observer.
#include <gtest/gtest.h>

#include <unistd.h>
#include <Eigen/Dense>

#include <fmt/format.h>
#include <cmath>
#include <iostream>

#include "CliTestUtil.hpp"
#include "MpmTestUtil.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/SymmetricTensor.hpp"
#include "gradmpm/materials/MaterialRegistry.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

using namespace gradmpm;
using gradmpm::test::slurp;
namespace fs = std::filesystem;

namespace {

/// A small-strain linear law with a non-symmetric tangent: isotropic D plus a coupling
/// c in D_xxyy only (sigma_xx gains c eps_yy, sigma_yy does not gain c eps_xx). History:
/// the strain and the largest compression -tr(eps) seen. `claim_symmetric` lies about
/// the tangent (R3's counter-example).
class ToyAnisotropic final : public Material {
 public:
  ToyAnisotropic(const IsotropicElasticity& e, double c, bool claim_symmetric)
      : Material(e, 0.0), D_(e.tensor()), claim_symmetric_(claim_symmetric) {
    D_(0, 4) += c;  // (xx, yy)
  }
  std::string model() const override { return "toy-anisotropic"; }
  bool finite_strain() const override { return false; }
  bool symmetric_tangent() const override { return claim_symmetric_; }
  const std::vector<StateVariable>& state_variables() const override {
    static const std::vector<StateVariable> vars = {
        {"elastic_strain", StateVariable::Kind::SymmetricTensor, 0.0, "small strain"},
        {"max_compression", StateVariable::Kind::Scalar, 0.0, "largest -tr(eps) so far"}};
    return vars;
  }
  void update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const override {
    const Mat3 g = dF - Mat3::Identity();
    const Mat3 eps = unpack_symmetric(state_n) + 0.5 * (g + g.transpose());
    out.stress = contract(D_, eps);
    pack_symmetric(eps, state);
    state[6] = std::max(state_n[6], -eps.trace());
  }
  void tangent(const MaterialResponse&, int, Mat9& A) const override { A = D_; }
  Mat3 elastic_strain(const double* state) const override { return unpack_symmetric(state); }
  double elastic_energy_density(const double* state) const override {  // its own D, not the isotropic one
    const Mat3 e = unpack_symmetric(state);
    return 0.5 * (e.array() * contract(D_, e).array()).sum();
  }

 private:
  Mat9 D_;
  bool claim_symmetric_;
};

void register_toy_law() {
  MaterialInfo info{"toy-anisotropic", "test only", isotropic_elasticity_keys(), {}};
  info.keys.push_back(
      {.name = "coupling", .type = KeyType::Number, .default_value = 0.0, .min = 0.0, .doc = "extra D_xxyy"});
  info.keys.push_back({.name = "claim_symmetric", .type = KeyType::Boolean, .default_value = false, .doc = "lie"});
  info.make = [](const CaseFile& cf, const std::string& prefix,
                 const MaterialInfo& self) -> std::shared_ptr<const Material> {
    const ElasticSolid s = read_elastic_solid(cf, prefix, self);
    return std::make_shared<ToyAnisotropic>(s.elasticity, read_number(cf, prefix, self.keys[3]),
                                            read_boolean(cf, prefix, self.keys[4]));
  };
  MaterialRegistry::instance().add(std::move(info));  // the one registration call
}

constexpr double kE = 100.0, kNu = 0.25, kC = 20.0, kTop = -0.01;

/// A unit square on rollers (base and left side), its top pushed down by 0.01: a
/// homogeneous state every linear basis reproduces exactly.
std::string block_case(const std::string& extra_material_keys = "") {
  return fmt::format(R"(
[grid]
origin = [0.0, 0.0]
cell_size = 0.25
cells = [4, 4]
[materials.toy]
model = "toy-anisotropic"
young = {}
poisson = {}
coupling = {}
{}
[[bodies]]
material = "toy"
min = [0.0, 0.0]
max = [1.0, 1.0]
[[constraints]]
face = "y-"
fix = ["y"]
[[constraints]]
face = "x-"
fix = ["x"]
[[constraints]]
face = "y+"
fix = ["y"]
displacement = [0.0, {}]
[load_steps]
count = 1
[output]
vtk_every = 1
)",
                     kE, kNu, kC, extra_material_keys, kTop);
}

/// Closed form: eps_yy = top displacement; sigma_xx = 0 gives eps_xx.
double closed_form_exx() {
  const IsotropicElasticity e(kE, kNu);
  return -(e.lambda + kC) * kTop / (e.lambda + 2.0 * e.mu);
}

struct Solved {
  MpmCase<2> c;
  std::vector<double> residuals;
};
Solved solve(const std::string& text, const std::vector<std::string>& sets = {}) {
  CaseFile cf = CaseFile::parse(text, "toy.toml", sets);
  Solved s{read_mpm_case<2>(cf), {}};
  run_quasi_static<2>(s.c.model, s.c.newton,
                      [&](const Model<2>&, const StepInfo& info) { s.residuals = info.residuals; });
  return s;
}

}  // namespace

TEST(Recipes, AMaterialDefinedInATestReadsItsKeysAndRunsFromACaseFile) {
  register_toy_law();
  const Solved s = solve(block_case());
  const auto& m = s.c.model;
  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0]->model(), "toy-anisotropic");
  EXPECT_EQ(m.points.state_stride, 7);
  // Its own key, with its range and the law's key list in the message.
  const std::string range =
      test::read_error<2>(CaseFile::parse(block_case(), "toy.toml", {"materials.toy.coupling=-1"}));
  EXPECT_NE(range.find("materials.toy.coupling (from --set): expected a number >= 0"), std::string::npos) << range;
  const std::string unknown = test::read_error<2>(CaseFile::parse(block_case("yield_stress = 3.0"), "toy.toml"));
  EXPECT_NE(unknown.find("materials.toy.yield_stress: unknown key"), std::string::npos) << unknown;
}

TEST(Recipes, ANonSymmetricTangentIsSolvedAsSuchNeverSymmetrised) {
  register_toy_law();
  const Solved s = solve(block_case());
  // One Newton iteration: the linear problem with its exact (non-symmetric) tangent.
  ASSERT_EQ(s.residuals.size(), 2u);
  EXPECT_LT(s.residuals.back(), 1e-12);
  const double exx = closed_form_exx();
  for (int p = 0; p < s.c.model.points.size(); ++p) {
    const Mat3 e = s.c.model.elastic_strain(p);
    EXPECT_NEAR(e(0, 0), exx, 1e-12) << "point " << p;
    EXPECT_NEAR(e(1, 1), kTop, 1e-12) << "point " << p;
    EXPECT_NEAR(s.c.model.points.stress[p](0, 0), 0.0, 1e-10) << "traction-free side";
  }
  // The same law claiming a symmetric tangent: CHOLMOD reads the lower triangle only,
  // the Newton direction is wrong, one iteration is not enough.
  std::vector<double> lying;
  try {
    lying = solve(block_case("claim_symmetric = true")).residuals;
  } catch (const SolverError&) {
  }
  std::cout << "non-symmetric tangent as such: " << s.residuals.size() - 1 << " iteration(s); symmetrised: "
            << (lying.empty() ? std::string("no convergence") : std::to_string(lying.size() - 1) + " iterations")
            << "\n";
  EXPECT_TRUE(lying.empty() || lying.size() > 2u) << "symmetrising gave the exact Newton step";
}

TEST(Recipes, StateVariablesReachTheOutputsByName) {
  register_toy_law();
  const fs::path dir = fs::temp_directory_path() / fmt::format("gradmpm-recipes-{}", ::getpid());
  fs::remove_all(dir);
  CaseFile cf = CaseFile::parse(block_case(), "toy.toml");
  run_mpm_case(cf, dir, true);
  const std::string csv = slurp(dir / "points_final.csv");
  const std::string header = csv.substr(0, csv.find('\n'));
  EXPECT_EQ(header,
            "id,X,Y,Z,x,y,z,sxx,syy,szz,sxy,syz,sxz,volume,mass,exx,eyy,ezz,exy,eyz,exz,max_compression,dissipation");
  // Every row's max_compression is -tr(eps) of the closed form.
  const double expected = -(closed_form_exx() + kTop);
  std::istringstream rows(csv.substr(csv.find('\n') + 1));
  int n = 0;
  for (std::string line; std::getline(rows, line); ++n) {
    const std::string before = line.substr(0, line.rfind(','));  // dissipation is the last column
    const double last = std::stod(before.substr(before.rfind(',') + 1));
    EXPECT_NEAR(last, expected, 1e-12) << line;
  }
  EXPECT_EQ(n, 64);
  const std::string vtu = slurp(dir / "points_0001.vtu");
  EXPECT_NE(vtu.find("Name=\"max_compression\""), std::string::npos);
  EXPECT_NE(vtu.find("Name=\"elastic_strain\""), std::string::npos);
  fs::remove_all(dir);
}

namespace {
/// UMFPACK under another name, counting its factorisations (R4).
int toy_factorisations = 0;
SystemDescription toy_description;
Eigen::MatrixXd toy_coordinates;
class CountingLu final : public LinearSolver {
 public:
  CountingLu() : lu_(make_linear_solver({.type = "umfpack"})) {}
  std::string name() const override { return "counting-lu"; }
  bool general() const override { return true; }
  void describe(const SystemDescription& d) override {
    toy_description = d;
    toy_coordinates = d.node_coordinates();
  }

 protected:
  void do_analyze(const SparseMatrix& A) override {
    EXPECT_EQ(toy_coordinates.rows() * 2, A.rows()) << "one row per node, 2 unknowns each";
    lu_->analyze(A);
  }
  void do_factorize(const SparseMatrix& A) override {
    ++toy_factorisations;
    lu_->factorize(A);
  }
  Vector do_solve(const Vector& b) const override { return lu_->solve(b); }

 private:
  std::unique_ptr<LinearSolver> lu_;
};
}  // namespace

TEST(Recipes, ALinearSolverDefinedInATestIsChosenFromTheCaseFile) {
  LinearSolverRegistry::instance().add({"counting-lu", "UMFPACK, counted (test only)", true,
                                        [](const LinearSolverSettings& s, MatrixKind) {
                                          EXPECT_EQ(s.options, "-toy_option 1");
                                          return std::make_unique<CountingLu>();
                                        },
                                        true});
  const std::string column = slurp(fs::path(GRADMPM_SOURCE_DIR) / "examples" / "column_2d.toml");
  CaseFile ref_cf = CaseFile::parse(column, "column_2d.toml", {"output.check=", "load_steps.count=3"});
  MpmCase<2> ref = read_mpm_case<2>(ref_cf);
  run_quasi_static<2>(ref.model, ref.newton);
  toy_factorisations = 0;
  CaseFile cf = CaseFile::parse(column, "column_2d.toml",
                                {"output.check=", "load_steps.count=3", "linear_solver.type=counting-lu",
                                 "linear_solver.options=\"-toy_option 1\""});
  MpmCase<2> c = read_mpm_case<2>(cf);
  EXPECT_EQ(c.newton.linear_solver.type, "counting-lu");
  const RunSummary summary = run_quasi_static<2>(c.model, c.newton);
  EXPECT_EQ(toy_factorisations, summary.total_iterations);
  EXPECT_EQ(toy_description.block_size, 2);
  ASSERT_GT(toy_coordinates.rows(), 0);
  for (Eigen::Index r = 0; r < toy_coordinates.rows(); ++r) {  // grid nodes: multiples of the cell size from the origin
    const double cx = (toy_coordinates(r, 0) - c.model.grid.origin()[0]) / c.model.grid.cell_size()[0];
    EXPECT_NEAR(cx, std::round(cx), 1e-9);
  }
  const std::string refused =
      test::read_error<2>(CaseFile::parse(column, "column_2d.toml", {"linear_solver.options=\"-ksp_type cg\""}));
  EXPECT_NE(refused.find("linear_solver.options (from --set): expected no options: \"cholmod\" takes none"),
            std::string::npos)
      << refused;
  double diff = 0.0, scale = 0.0;
  for (int p = 0; p < c.model.points.size(); ++p) {
    diff = std::max(diff, (c.model.points.position[p] - ref.model.points.position[p]).norm());
    scale = std::max(scale, (ref.model.points.position[p] - ref.model.points.original_position[p]).norm());
  }
  EXPECT_LT(diff, 1e-10 * scale);
}

namespace {
/// Records what it sees after each step (R5).
class RecordingStage final : public PostStepStage<2> {
 public:
  std::string name() const override { return "recording"; }
  void after_step(Model<2>& m, const StepInfo& info) override {
    log.push_back(fmt::format("stage {}", info.step));
    double top = 0.0;
    for (const auto& x : m.points.position) top = std::max(top, x[1]);
    tops.push_back(top);
  }
  std::vector<std::string> log;
  std::vector<double> tops;
};
}  // namespace

TEST(Recipes, APostStepStageRunsAfterEveryStepOnTheCommittedStateBeforeTheObserver) {
  const std::string column = slurp(fs::path(GRADMPM_SOURCE_DIR) / "examples" / "column_2d.toml");
  CaseFile cf = CaseFile::parse(column, "column_2d.toml", {"output.check=", "load_steps.count=4"});
  MpmCase<2> c = read_mpm_case<2>(cf);
  RecordingStage stage;
  std::vector<double> observed_tops;
  const RunSummary summary =
      run_quasi_static<2>(c.model, c.newton, {&stage}, [&](const Model<2>& m, const StepInfo& info) {
        stage.log.push_back(fmt::format("observer {}", info.step));
        double top = 0.0;
        for (const auto& x : m.points.position) top = std::max(top, x[1]);
        observed_tops.push_back(top);
      });
  ASSERT_EQ(summary.steps, 4);
  ASSERT_EQ(stage.log.size(), 8u);
  for (int s = 1; s <= 4; ++s) {
    EXPECT_EQ(stage.log[2 * (s - 1)], fmt::format("stage {}", s));
    EXPECT_EQ(stage.log[2 * (s - 1) + 1], fmt::format("observer {}", s));
    EXPECT_EQ(stage.tops[s - 1], observed_tops[s - 1]) << "the stage saw the committed positions";
  }
  EXPECT_LT(stage.tops.back(), stage.tops.front()) << "the column settles step by step";
}
