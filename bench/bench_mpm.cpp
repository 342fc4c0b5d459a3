// bench_mpm: what one Newton iteration of the implicit MPM costs, phase by phase, as the
// problem grows (docs/performance.md). Never part of the tests.
//
//   build/bench/bench_mpm [--quick] [--threads N] [--csv FILE] [--only CASE:SIZE] [--solver NAME] [--options S]
//   mpirun -n R build/bench/bench_mpm ... --solver petsc   (R ranks, docs/parallel.md)
//   (--solver: the case files' linear_solver.type, cholmod by default; with
//   pcg, factor_s is the incomplete-Cholesky preconditioner and solve_s the CG iterations;
//   with petsc, factor_s is the preconditioner's set-up (GAMG) and solve_s the Krylov
//   iterations, krylov_its of them per Newton iteration; --options: linear_solver.options)
//   (--only runs one size of one case, e.g. column_2d:224 or footing_2d:4, for profiling)
//
// Cases (built from case-file text, so they are the code paths users run):
//   column_2d  a square block under self-weight (Hencky, nu = 0.3), base fixed, sides on
//              rollers, cpGIMP, 2 points per cell and direction; n x n cells
//   column_2d_dynamic the 2D column with [time] (Newmark, lumped mass, dt = 0.05, gravity in
//              full from t = 0) instead of load steps: what the points' inertia costs a Newton
//              iteration (the mass's projection, M a in the residual, M in the tangent)
//   column_2d_consolidation the 2D column as a saturated soil (coupled u-p, [pore_pressure])
//              consolidating under its weight in time steps of 0.05, drained at its top:
//              what the pore pressure costs a Newton iteration (n x n cells: the same
//              displacement dof as column_2d, and a pressure per node)
//   column_2d_axisymmetric the 2D column as an axisymmetric one ([mpm] axisymmetric: a
//              cylinder of radius 10 in a smooth rigid pipe, on the axis x = 0): what the
//              hoop terms cost a Newton iteration against column_2d's at the same dof
//   column_3d  the same in 3D; n x n x n cells
//   footing_2d examples/footing_2d.toml refined by a factor (uGIMP)
//   tresca_2d  examples/footing_tresca_2d.toml (von Mises, plastic under the footing)
//              refined by a factor; r = 12 is 1.2e5 dof
//   biaxial_2d examples/biaxial_2d.toml (softening von Mises, implicit-gradient
//              regularisation) refined by a factor, in 10 load steps, so that step 2 is past
//              the peak: the band is forming; r = 7 is 1.1e5 dof. Run three times: regularised
//              and staggered (biaxial_2d), regularised and monolithic (biaxial_2d_monolithic:
//              kappa_bar a nodal unknown beside du), and with the [regularisation] section
//              removed (biaxial_2d_classical)
// For each size the case's load steps are solved up to the reported one (--step K, 2 by
// default) and that step's phases are reported per Newton iteration. The first step is
// not representative: it starts from points at their generated, cell-aligned positions,
// where a GIMP stencil holds 2^dim nodes; once the points have moved it holds 3^dim, and
// the pattern (9 -> 25 node neighbours in 2D), the assembly and the factorisation all
// grow. Per iteration: pattern, update and analysis (done once per step) are
// divided by the step's iterations; assembly, factorisation and solve are per iteration.
// gradient_s is one e-RA smoothing of the strain (6 components) after the step.
// peak_mib is the process's peak resident memory so far (sizes grow, so it is this size's).
// wall_s is the whole load step's wall time per Newton iteration (its cuts included): the
// phases plus what no phase counts (the Dirichlet elimination, residual norms, copies),
// less what ran at the same time: with CHOLMOD the step's analysis runs on one thread
// while the others assemble its first tangent (run_beside), and both phases count it.
// ratio = (wall - factor - solve) / (factor + solve): everything that is not the numeric
// factorisation and solve, against them (wall, not the sum of the timed phases, so the
// work no phase times counts too).
// Under mpirun (R ranks, the `ranks` column) the figures are rank 0's: its phases include
// its waits in the sums over the ranks, so they show the slowest rank's pace; peak_mib is
// rank 0's process (each rank makes and holds its own points); `points` is the body's.
// Only rank 0 prints and writes the CSV. PETSc's own profile: PETSC_OPTIONS=-log_view.
// "with gradient" adds a gradient step after the load step (apply = "each_step"), shared
// out over the step's iterations, its factorisation and solves counted with the solver's.
// nonlocal_s is the regularisation's own work per Newton iteration (the kappa_bar
// operator and solves of the staggered iterations); "regularisation adds" is nonlocal_s
// against the rest of the iteration. staggers: the step's staggered iterations.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <omp.h>
#include <sys/resource.h>

#include <array>
#include <cstring>
#include <exception>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "gradmpm/app/MpiLaunch.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/tuning/ProcessTuning.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/core/Timer.hpp"

using namespace gradmpm;

namespace {

/// "[v0, v1]" or "[v0, v1, v2]": the first dim entries.
std::string point(int dim, std::array<double, 3> v) {
  std::vector<double> first(v.begin(), v.begin() + dim);
  return fmt::format("[{}]", fmt::join(first, ", "));
}

/// A block of side 10 under self-weight (Hencky, nu = 0.3, cpGIMP), n cells per side and
/// one cell of margin around it: the base held, each lateral face on rollers.
std::string column(int dim, int n) {
  const double h = 10.0 / n, lo = -h;
  const std::vector<int> cells(dim, n + 2);
  const std::array<char, 3> axis{'x', 'y', 'z'};
  std::vector<std::string> all_axes;
  for (int d = 0; d < dim; ++d) all_axes.push_back(fmt::format("\"{}\"", axis[d]));
  std::string t = fmt::format(R"(
[grid]
origin = {}
cell_size = {}
cells = [{}]
[basis]
type = "cpgimp"
[materials.soil]
model = "hencky"
young = 1000.0
poisson = 0.3
density = 1.0
[[bodies]]
material = "soil"
min = {}
max = {}
[loads]
gravity = {}
)",
                              point(dim, {lo, lo, lo}), h, fmt::join(cells, ", "), point(dim, {0.0, 0.0, 0.0}),
                              point(dim, {10.0, 10.0, 10.0}), point(dim, {0.0, dim == 2 ? -10.0 : 0.0, -10.0}));
  auto constraint = [&](std::array<double, 3> min, std::array<double, 3> max, const std::string& fix) {
    t += fmt::format("[[constraints]]\nmin = {}\nmax = {}\nfix = [{}]\n", point(dim, min), point(dim, max), fix);
  };
  std::array<double, 3> base_max{20.0, 20.0, 20.0};
  base_max[dim - 1] = 0.0;
  constraint({lo, lo, lo}, base_max, fmt::format("{}", fmt::join(all_axes, ", ")));
  for (int d = 0; d + 1 < dim; ++d) {  // rollers on the two faces normal to d
    std::array<double, 3> max{20.0, 20.0, 20.0}, min{lo, lo, lo};
    max[d] = 0.0;
    constraint({lo, lo, lo}, max, all_axes[d]);
    min[d] = 10.0;
    constraint(min, {20.0, 20.0, 20.0}, all_axes[d]);
  }
  return t + "[load_steps]\ncount = 10\n[output]\nvtk_every = 0\n";
}

/// The column about the axis x = 0 (its x = 0 rollers on the axis, its x = 10 ones a
/// smooth pipe).
std::string axisymmetric_column(int n) {
  std::string t = column(2, n);
  const std::string steps = "[load_steps]";
  return t.insert(t.find(steps), "[mpm]\naxisymmetric = true\n");
}

/// The column with the points' inertia: time steps of 0.05 (the column's first period is
/// about 1) instead of load steps.
std::string dynamic_column(int dim, int n) {
  std::string t = column(dim, n);
  const std::string steps = "[load_steps]\ncount = 10\n";
  return t.replace(t.find(steps), steps.size(), "[time]\ndt = 0.05\nend_time = 1.0\n");
}

/// The 2D column as a saturated soil consolidating under its weight (coupled u-p, [time]
/// without inertia), drained at its top: what the pore pressure costs a Newton iteration
/// (a third more equations, a non-symmetric tangent).
std::string consolidating_column(int n) {
  std::string t = column(2, n);
  const double h = 10.0 / n;
  const std::string steps = "[load_steps]\ncount = 10\n";
  t.replace(t.find(steps), steps.size(), "[time]\ndt = 0.05\nend_time = 1.0\ninertia = false\n");
  const std::string soil = "density = 1.0\n";
  t.replace(t.find(soil), soil.size(), soil + "porosity = 0.4\npermeability = 1e-3\nfluid_density = 0.5\n");
  return t + fmt::format("[pore_pressure]\ndrainage = \"coupled\"\n[[pressure_constraints]]\nmin = [{}, {}]\nmax = [{}, {}]\n",
                         -h, 10.0 - 2.0 * h, 10.0 + h, 10.0 + h);
}

double peak_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;  // kB on Linux
}

struct StopAfterStep {};

/// Which load step is reported (--step; 2 by default, see the header).
int reported_step = 2;

template <int dim>
void bench(const std::string& name, CaseFile cf, std::ofstream& csv, int threads) {
  MpmCase<dim> c = read_mpm_case<dim>(cf, ranks::distributed());  // (each rank its own points)
  Model<dim>& m = c.model;
  const NewtonSettings& newton = c.newton;
  StepInfo step;
  try {
    run_quasi_static<dim>(m, newton, [&](const Model<dim>&, const StepInfo& info) {
      step = info;  // its phases (the grid-field callbacks are valid only inside the call)
      if (info.step == reported_step) throw StopAfterStep{};
    });
  } catch (const StopAfterStep&) {
  }
  const auto t0 = Clock::now();
  const double gradient_solver_s =
      smooth_total<dim>(m, {GradientVariant::E_RA, 0.5, GradientApply::End, GradientFields::Grid, newton.linear_solver},
                        step.after.ordering.nodes)
          .solver_seconds;
  const double gradient_s = seconds_since(t0);
  double owned = m.points.size();  // a distributed run's rank holds its own points: the sum is the body's
  ranks::sum(&owned, 1);
  const long long points = static_cast<long long>(owned);
  const PhaseTimes& t = step.phases;
  const double its = std::max(1, t.iterations);
  const double pattern = t.pattern / its, assembly = t.assembly / its, analysis = t.analysis / its,
               factor = t.factor / its, solve = t.solve / its, update = t.update / its;
  const double wall = step.seconds / its;
  const double ratio = (wall - factor - solve) / (factor + solve);
  // With a gradient step after every load step (apply = "each_step"), shared out over
  // the step's iterations; its own factorisation and solves count as solver time.
  const double ratio_g =
      (wall - factor - solve + (gradient_s - gradient_solver_s) / its) / (factor + solve + gradient_solver_s / its);
  const double nonlocal = t.nonlocal / its;
  // The solver of the tangent: a non-symmetric one (F-bar, non-associated flow) goes to
  // linear_solver.general.
  const std::string& solver = m.symmetric_tangent() ? newton.linear_solver.type : newton.linear_solver.general;
  const double krylov = t.krylov / its;
  const std::string row = fmt::format(
      "{},{},{},{},{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.1f},{:.6f},{},{},{:.1f},{:.6f},{}", name,
      dim, step.dofs, points, step.nonzeros, threads, pattern, assembly, analysis, factor, solve, update,
      gradient_s, peak_mib(), nonlocal, step.staggers, solver, krylov, wall, ranks::size());
  if (ranks::rank() != 0) return;
  csv << row << "\n";
  csv.flush();
  if (ranks::distributed()) fmt::print("{:<11} {} ranks\n", name, ranks::size());
  fmt::print(
      "{:<11} {} dof {:>8}  points {:>8}  nnz {:>10}  its {}  cuts {}  pattern {:.4f}  assembly {:.4f}  "
      "analysis {:.4f}  factor {:.4f}  solve {:.4f}{}  update {:.4f}  wall {:.4f}  gradient {:.4f} (solver {:.4f})  "
      "peak {:.0f} MiB  ratio {:.2f}  with gradient {:.2f}\n",
      name, solver, step.dofs, points, step.nonzeros, t.iterations, step.cuts, pattern, assembly, analysis,
      factor, solve, t.krylov > 0 ? fmt::format(" ({:.0f} Krylov its)", krylov) : "", update, wall, gradient_s,
      gradient_solver_s, peak_mib(), ratio, ratio_g);
  if (step.staggers > 0)
    fmt::print("{:<11} staggers {}  nonlocal {:.4f} per Newton iteration: regularisation adds {:.1f} % to one\n", "",
               step.staggers, nonlocal, 100.0 * nonlocal / (pattern + assembly + analysis + factor + solve + update));
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  // The process is tuned as gradmpm is (tuning/ProcessTuning.hpp: --no-tuning, GRADMPM_TUNING).
  // Under mpirun: an MPI session for the run (PETSc then splits the solves, the driver the
  // point loops), rank 0 reporting.
  std::optional<ranks::Session> session;
  if (mpi_launch_from_environment().size > 1) session.emplace(&argc, &argv);
  bool quick = false;
  int threads = omp_get_max_threads();
  std::string csv_path = "bench-results.csv";
  std::string only;  // "case:size"
  std::string solver = "cholmod", options;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick"))
      quick = true;
    else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc)
      csv_path = argv[++i];
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc)
      only = argv[++i];
    else if (!std::strcmp(argv[i], "--solver") && i + 1 < argc)
      solver = argv[++i];
    else if (!std::strcmp(argv[i], "--options") && i + 1 < argc)
      options = argv[++i];
    else if (!std::strcmp(argv[i], "--no-tuning"))
      continue;  // read before main (tuning/ProcessTuning.hpp)
    else if (!std::strcmp(argv[i], "--step") && i + 1 < argc)
      reported_step = std::max(1, std::atoi(argv[++i]));
    else {
      fmt::print(stderr,
                 "usage: bench_mpm [--quick] [--threads N] [--csv FILE] [--only CASE:SIZE] [--solver NAME] [--options "
                 "STRING] [--step K] [--no-tuning]\n");
      return 2;
    }
  }
  omp_set_num_threads(threads);
  std::ofstream csv(ranks::rank() == 0 ? csv_path : "/dev/null");
  if (!csv) {
    fmt::print(stderr, "bench_mpm: cannot write {}\n", csv_path);
    return 2;
  }
  csv << "case,dim,dof,points,nnz,threads,pattern_s,assembly_s,analysis_s,factor_s,solve_s,update_s,gradient_s,peak_"
         "mib,nonlocal_s,staggers,solver,krylov_its,wall_s,ranks\n";
  if (ranks::rank() == 0) {
    fmt::print("bench_mpm: {} rank(s), {} thread(s) each, {} sweep, {}; seconds per Newton iteration\n", ranks::size(),
               threads, quick ? "quick" : "full", tuning::summary());
  }

  std::vector<int> n2 = quick ? std::vector<int>{20, 64, 224} : std::vector<int>{20, 64, 224, 448, 708};
  std::vector<int> dynamic2 = quick ? std::vector<int>{20, 224} : std::vector<int>{20, 224};
  std::vector<int> pore2 = quick ? std::vector<int>{20, 224} : std::vector<int>{20, 224};
  std::vector<int> axi2 = quick ? std::vector<int>{20, 224} : std::vector<int>{20, 224};
  std::vector<int> n3 = quick ? std::vector<int>{6, 14} : std::vector<int>{6, 14, 24};
  std::vector<int> refine = quick ? std::vector<int>{1, 4} : std::vector<int>{1, 4, 8, 16, 32};
  std::vector<int> plastic = quick ? std::vector<int>{1, 4} : std::vector<int>{1, 4, 12};
  std::vector<int> biaxial = quick ? std::vector<int>{1} : std::vector<int>{1, 3, 7};
  if (!only.empty()) {
    const auto colon = only.find(':');
    const std::string name = only.substr(0, colon);
    const int size = colon == std::string::npos ? 0 : std::atoi(only.c_str() + colon + 1);
    if (size <= 0 || (name != "column_2d" && name != "column_2d_dynamic" && name != "column_2d_consolidation" &&
                      name != "column_2d_axisymmetric" && name != "column_3d" &&
                      name != "footing_2d" && name != "tresca_2d" && name != "biaxial_2d")) {
      fmt::print(stderr,
                 "bench_mpm: --only expects column_2d:N, column_2d_dynamic:N, column_2d_consolidation:N, "
                 "column_2d_axisymmetric:N, column_3d:N, "
                 "footing_2d:R, tresca_2d:R "
                 "or biaxial_2d:R with N, R > 0, not '{}'\n",
                 only);
      return 2;
    }
    dynamic2 = name == "column_2d_dynamic" ? std::vector<int>{size} : std::vector<int>{};
    pore2 = name == "column_2d_consolidation" ? std::vector<int>{size} : std::vector<int>{};
    axi2 = name == "column_2d_axisymmetric" ? std::vector<int>{size} : std::vector<int>{};
    n2 = name == "column_2d" ? std::vector<int>{size} : std::vector<int>{};
    n3 = name == "column_3d" ? std::vector<int>{size} : std::vector<int>{};
    refine = name == "footing_2d" ? std::vector<int>{size} : std::vector<int>{};
    plastic = name == "tresca_2d" ? std::vector<int>{size} : std::vector<int>{};
    biaxial = name == "biaxial_2d" ? std::vector<int>{size} : std::vector<int>{};
  }
  const std::string solver_key = fmt::format("linear_solver.type=\"{}\"", solver),
                    options_key = fmt::format("linear_solver.options=\"{}\"", options);
  for (int n : n2)
    bench<2>("column_2d", CaseFile::parse(column(2, n), "column_2d", {solver_key, options_key}), csv, threads);
  for (int n : dynamic2)
    bench<2>("column_2d_dynamic", CaseFile::parse(dynamic_column(2, n), "column_2d_dynamic", {solver_key, options_key}),
             csv, threads);
  for (int n : pore2)
    bench<2>("column_2d_consolidation",
             CaseFile::parse(consolidating_column(n), "column_2d_consolidation", {solver_key, options_key}), csv,
             threads);
  for (int n : axi2)
    bench<2>("column_2d_axisymmetric",
             CaseFile::parse(axisymmetric_column(n), "column_2d_axisymmetric", {solver_key, options_key}), csv, threads);
  for (int n : n3)
    bench<3>("column_3d", CaseFile::parse(column(3, n), "column_3d", {solver_key, options_key}), csv, threads);
  const std::string footing = std::string(GRADMPM_SOURCE_DIR) + "/examples/footing_2d.toml";
  for (int r : refine) {
    const double h = 0.125 / r;
    bench<2>(
        "footing_2d",
        CaseFile::load(
            footing,
            {fmt::format("grid.origin=[{},{}]", -h, -2 * h), fmt::format("grid.cell_size={}", h),
             fmt::format("grid.cells=[{},{}]", 35 * r, 20 * r), fmt::format("constraints[0].min=[{},{}]", -h, -2 * h),
             fmt::format("constraints[1].min=[{},{}]", -h, -2 * h),
             fmt::format("point_loads[0].min=[0.0,{}]", 2.0 - h / 2),
             fmt::format("point_loads[0].force=[0.0,{}]", -15.0 / r), "output.vtk_every=0", solver_key, options_key}),
        csv, threads);
  }
  const std::string tresca = std::string(GRADMPM_SOURCE_DIR) + "/examples/footing_tresca_2d.toml";
  for (int r : plastic) {
    const double h = 0.25 / r;
    bench<2>(
        "tresca_2d",
        CaseFile::load(
            tresca,
            {fmt::format("grid.origin=[{},{}]", -h, -h), fmt::format("grid.cell_size={}", h),
             fmt::format("grid.cells=[{},{}]", 20 * r + 2, 20 * r + 2),
             fmt::format("constraints[0].min=[{},{}]", -h, -h), fmt::format("constraints[0].max=[{},0.0]", 5.0 + h),
             fmt::format("constraints[1].min=[{},{}]", -h, h), fmt::format("constraints[1].max=[0.0,{}]", 5.0 + h),
             fmt::format("constraints[2].min=[5.0,{}]", h), fmt::format("constraints[2].max=[{},{}]", 5.0 + h, 5.0 + h),
             "output.vtk_every=0", "output.plot=false", solver_key, options_key}),
        csv, threads);
  }
  const std::string biaxial_case = std::string(GRADMPM_SOURCE_DIR) + "/examples/biaxial_2d.toml";
  for (int r : biaxial) {
    const double h = 1.0 / (24 * r);
    const std::vector<std::string> refined{fmt::format("grid.origin=[-0.25,{}]", -2 * h),
                                           fmt::format("grid.cell_size={}", h),
                                           fmt::format("grid.cells=[{},{}]", 36 * r, 52 * r + 2),
                                           "rigid_boxes[0].displacement=[0.0,-0.045]",  // as measured
                                           "load_steps.count=10",
                                           "output.vtk_every=0",
                                           "output.plot=false",
                                           solver_key,
                                           options_key};
    // Past the peak Newton may not find a step (one cell of band, classical; or at the
    // finest grid): said, and the next run is measured.
    try {
      bench<2>("biaxial_2d", CaseFile::load(biaxial_case, refined), csv, threads);
    } catch (const std::exception& e) {
      fmt::print("biaxial_2d r = {}: {}\n", r, e.what());
    }
    try {  // the same, kappa_bar beside du in one Newton iteration (mpm/GradientCoupling.hpp)
      std::vector<std::string> monolithic = refined;
      monolithic.push_back("regularisation.coupling=monolithic");
      bench<2>("biaxial_2d_monolithic", CaseFile::load(biaxial_case, monolithic), csv, threads);
    } catch (const std::exception& e) {
      fmt::print("biaxial_2d_monolithic r = {}: {}\n", r, e.what());
    }
    try {
      CaseFile classical = CaseFile::load(biaxial_case, refined);
      classical.remove_section("regularisation");
      bench<2>("biaxial_2d_classical", std::move(classical), csv, threads);
    } catch (const std::exception& e) {
      fmt::print("biaxial_2d_classical r = {}: {}\n", r, e.what());
    }
  }
  if (ranks::rank() == 0) fmt::print("wrote {}\n", csv_path);
}
