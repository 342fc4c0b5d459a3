// Requirement (performance issue): multithreaded assembly gives the same operators and
// the same MPM solution as the single-threaded one. Points are scattered by colour
// (Assembler::for_each_point_disjoint), so every nodal sum is formed in the same order
// whatever the thread count: the results are identical bit for bit. The threshold below
// which loops stay serial (core/Parallel.hpp) is lowered so that these small models run
// on threads; a counter checks that more than one thread took part.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>
#include <vector>

#include <Eigen/Dense>

#include "MpmTestUtil.hpp"
#include "gradmpm/solver/Assembler.hpp"

using namespace gradmpm;
using namespace gradmpm::test;

namespace {
struct Threads {  // sets the OpenMP thread count and the threading threshold for a scope
  int saved, saved_min;
  explicit Threads(int n) : saved(omp_get_max_threads()), saved_min(min_points_for_threads()) {
    omp_set_num_threads(n);
    min_points_for_threads() = 1;
  }
  ~Threads() {
    omp_set_num_threads(saved);
    min_points_for_threads() = saved_min;
  }
};
}  // namespace

TEST(Parallel, AssemblyEqualsSerialAssembly) {
  const int n = 48;
  const Grid<2> grid(Vec<2>(0.0, 0.0), Vec<2>(1.0 / n, 1.0 / n), {n, n});
  MaterialPoints<2> pts;
  add_regular_points<2>(
      grid, {0, 0}, {n, n}, 3, [](const Vec<2>&) { return true; }, 0, 1.0, pts);
  for (int p = 0; p < pts.size(); ++p) pts.position[p] += Vec<2>(0.1 / n * std::sin(p), 0.1 / n * std::cos(3.0 * p));
  const auto st = evaluate_stencils(grid, pts, BasisKind::MPM);  // perturbed points stay h/6 inside
  const DofMap dofs(st, grid.num_nodes(), 1);
  const SparseMatrix pattern = build_pattern(st, dofs);
  const Assembler<2> as(st, pts, dofs, &grid);
  SparseMatrix serial = pattern, threaded = pattern;
  {
    Threads t(1);
    as.add_helmholtz(serial, 0.01);
  }
  {
    Threads t(4);
    as.add_helmholtz(threaded, 0.01);
  }
  const Eigen::Map<const Vector> a(serial.valuePtr(), serial.nonZeros()), b(threaded.valuePtr(), threaded.nonZeros());
  EXPECT_EQ((a - b).lpNorm<Eigen::Infinity>(), 0.0);
  EXPECT_GT(a.lpNorm<Eigen::Infinity>(), 0.0);
}

// The strips' runs (points of one stencil, found once when the strips are built) hold the
// points of one stencil each, every point once, and a matrix assembled by them equals the
// point-by-point sum (to round-off: the order of the additions differs).
TEST(Parallel, RunsOfTheStripsHoldOneStencilAndGiveThePointByPointSum) {
  const Model<2> m = make_column<2>(12, BasisKind::CPGIMP);  // 2 points per cell and direction
  const auto st = evaluate_stencils(m.grid, m.points, BasisKind::MPM);
  const DofMap dofs(st, m.grid.num_nodes(), 1);
  const Assembler<2> as(st, m.points, dofs, &m.grid);
  std::vector<int> visits(m.points.size(), 0);
  int runs = 0;
  as.for_each_run([&](const int* first, const int* last) {
    ++runs;
    for (const int* p = first; p != last; ++p) {
      ++visits[*p];
      EXPECT_EQ(st[*p].count, st[*first].count);
      for (int a = 0; a < st[*p].count; ++a) EXPECT_EQ(st[*p].node[a], st[*first].node[a]);
    }
  });
  EXPECT_EQ(std::count(visits.begin(), visits.end(), 1), m.points.size());
  EXPECT_EQ(runs * 4, m.points.size());  // the 4 points of a cell share its 4 nodes (linear basis)
  SparseMatrix M = build_pattern(st, dofs);
  as.add_mass(M);
  const int n = dofs.num_dofs();
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(n, n);
  for (int p = 0; p < m.points.size(); ++p)
    for (int a = 0; a < st[p].count; ++a)
      for (int b = 0; b < st[p].count; ++b)
        expected(dofs.dof(st[p].node[a], 0), dofs.dof(st[p].node[b], 0)) +=
            st[p].N[a] * st[p].N[b] * m.points.volume[p];
  EXPECT_LT((Eigen::MatrixXd(M) - expected).norm(), 1e-14 * expected.norm());
}

TEST(Parallel, SmallLoopsRunOnThreadsOnlyAboveTheThreshold) {
  const Model<2> m = make_column<2>(16, BasisKind::CPGIMP);
  const auto st = evaluate_stencils(m.grid, m.points, BasisKind::CPGIMP);
  const DofMap dofs(st, m.grid.num_nodes(), 1);
  const Assembler<2> as(st, m.points, dofs, &m.grid);
  auto team_sizes = [&] {
    int most = 0;
    as.for_each_point_disjoint([&](int) {
#pragma omp critical
      most = std::max(most, omp_get_num_threads());
    });
    return most;
  };
  ASSERT_LT(m.points.size(), min_points_for_threads());
  EXPECT_EQ(team_sizes(), 1);  // below the threshold: serial
  Threads t(4);
  EXPECT_EQ(team_sizes(), 4);
}

// run_beside (core/Parallel.hpp), by which the Newton driver analyses the tangent's pattern
// on one thread while the others assemble it: both jobs run, at the same time (each waits,
// boundedly, to see the other started), the serial one on the calling thread, the other's
// regions on the remaining threads; an exception of either comes out after both ran, the
// work's first; with one thread, the work and then the serial job.
TEST(Parallel, RunBesideRunsBothJobsAtOnceAndRethrowsAfterBoth) {
  const auto wait_for = [](const std::atomic<bool>& flag) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (!flag && std::chrono::steady_clock::now() < until) std::this_thread::yield();
    return flag.load();
  };
  {
    Threads t(4);
    std::atomic<bool> serial_started{false}, work_started{false};
    bool serial_saw_work = false, work_saw_serial = false;
    int serial_thread = -1, work_team = 0;
    run_beside(
        [&] {
          serial_thread = omp_get_thread_num();
          serial_started = true;
          serial_saw_work = wait_for(work_started);
        },
        [&] {
          work_started = true;
          work_saw_serial = wait_for(serial_started);
#pragma omp parallel
#pragma omp single
          work_team = omp_get_num_threads();
        });
    EXPECT_TRUE(serial_saw_work);
    EXPECT_TRUE(work_saw_serial);
    EXPECT_EQ(serial_thread, 0);
    EXPECT_EQ(work_team, 3);
    EXPECT_EQ(omp_get_max_threads(), 4);  // the caller's settings as they were
    EXPECT_EQ(omp_get_level(), 0);

    bool serial_ran = false, work_ran = false;
    try {
      run_beside(
          [&] {
            serial_ran = true;
            throw std::runtime_error("serial");
          },
          [&] {
            work_ran = true;
            throw std::runtime_error("work");
          });
      ADD_FAILURE() << "nothing rethrown";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "work");
    }
    EXPECT_TRUE(serial_ran && work_ran);
    EXPECT_THROW(run_beside([] { throw std::runtime_error("serial"); }, [] {}), std::runtime_error);
  }
  Threads t(1);
  std::vector<int> order;
  run_beside([&] { order.push_back(2); }, [&] { order.push_back(1); });
  EXPECT_EQ(order, (std::vector<int>{1, 2}));
}

TEST(Parallel, MpmSolutionEqualsSerialSolution) {
  Model<2> serial = make_column<2>(16, BasisKind::CPGIMP), threaded = make_column<2>(16, BasisKind::CPGIMP);
  NewtonSettings s;
  s.load_steps = 4;
  {
    Threads t(1);
    run_quasi_static<2>(serial, s);
  }
  {
    Threads t(4);
    run_quasi_static<2>(threaded, s);
  }
  for (int p = 0; p < serial.points.size(); ++p) {
    EXPECT_EQ(serial.points.position[p], threaded.points.position[p]);
    EXPECT_EQ(serial.points.stress[p], threaded.points.stress[p]);
  }
}

// The load step's analysis beside its first tangent (NewtonSettings::analysis_beside,
// run_beside): always there, never there, and as measured give the same MPM solution bit
// for bit (4 threads: the tangent assembled on 3 meanwhile), and the steps say where
// their analyses ran.
TEST(Parallel, AnalysisBesideTheFirstTangentGivesTheSameSolution) {
  using Mode = NewtonSettings::AnalysisBeside;
  std::vector<Model<2>> runs;
  std::vector<int> besides;
  Threads t(4);
  for (const Mode mode : {Mode::Never, Mode::Always, Mode::Measured}) {
    Model<2> m = make_column<2>(16, BasisKind::CPGIMP);
    NewtonSettings s;
    s.load_steps = 4;
    s.analysis_beside = mode;
    int beside = 0, analyses = 0;
    run_quasi_static<2>(m, s, [&](const Model<2>&, const StepInfo& info) {
      beside += info.phases.beside;
      analyses += info.phases.analyses;
    });
    if (mode == Mode::Never) EXPECT_EQ(beside, 0);
    if (mode == Mode::Always) EXPECT_EQ(beside, analyses);
    EXPECT_GT(analyses, 0);
    runs.push_back(std::move(m));
  }
  for (std::size_t k = 1; k < runs.size(); ++k)
    for (int p = 0; p < runs[0].points.size(); ++p) {
      EXPECT_EQ(runs[0].points.position[p], runs[k].points.position[p]);
      EXPECT_EQ(runs[0].points.stress[p], runs[k].points.stress[p]);
    }
}

// The schedule behind the bit-for-bit results above: runs given to threads at the same
// time touch disjoint nodes. Each run claims its stencil's nodes (an atomic flag per
// node) while it works and counts a clash when a node is already claimed; GIMP stencils
// of moved points span 3 nodes per direction, the widest the strips allow. Every point
// must be visited once. (Checked to fail with strips one anchor row wide, where strips
// of one parity are only two rows apart.)
template <int dim>
void expect_concurrent_runs_touch_disjoint_nodes(int n) {
  Vec<dim> h;
  h.setConstant(1.0 / n);
  std::array<int, dim> cells;
  cells.fill(n);
  const Grid<dim> grid(Vec<dim>::Zero(), h, cells);
  MaterialPoints<dim> pts;
  std::array<int, dim> lo, hi;
  lo.fill(1);
  hi.fill(n - 1);
  add_regular_points<dim>(
      grid, lo, hi, 2, [](const Vec<dim>&) { return true; }, 0, 1.0, pts);
  for (int p = 0; p < pts.size(); ++p)
    for (int d = 0; d < dim; ++d) pts.position[p][d] += 0.2 / n * std::sin(1.7 * p + d);
  const auto st = evaluate_stencils(grid, pts, BasisKind::UGIMP);
  const DofMap dofs(st, grid.num_nodes(), 1);
  const Assembler<dim> as(st, pts, dofs, &grid);
  std::vector<std::atomic<int>> claimed(grid.num_nodes());
  std::vector<int> visits(pts.size(), 0);
  std::atomic<int> clashes{0}, widest{0};
  Threads t(4);
  as.for_each_run([&](const int* first, const int* last) {
    const Stencil<dim>& s = st[*first];
    for (int a = 0; a < s.count; ++a)
      if (claimed[s.node[a]].exchange(1)) ++clashes;
    widest = std::max(widest.load(), s.count);
    double busy = 0.0;  // hold the claim a while, so that a clash has time to happen
    for (int k = 0; k < 2000; ++k) busy += std::sqrt(double(k + *first));
    for (const int* p = first; p != last; ++p) visits[*p] += busy > 0.0 ? 1 : 2;
    for (int a = 0; a < s.count; ++a) claimed[s.node[a]] = 0;
  });
  EXPECT_EQ(clashes.load(), 0);
  EXPECT_EQ(widest.load(), ipow(3, dim));
  EXPECT_EQ(std::count(visits.begin(), visits.end(), 1), pts.size());
}

TEST(Parallel, ConcurrentRunsTouchDisjointNodes) {
  expect_concurrent_runs_touch_disjoint_nodes<2>(40);
  expect_concurrent_runs_touch_disjoint_nodes<3>(12);
}
