// Requirements on the F-bar method (mpm/FBar.hpp):
//  R1 the assembled tangent is the derivative of the assembled internal force (central
//     differences, 1e-6 relative), with and without F-bar, in a plastic state of a
//     distorted GIMP block: F-bar's cell coupling and its non-symmetric local part are
//     consistent;
//  R2 the points of one cell share one volume change: after a step every point of a
//     cell has the same Jbar, and with F-bar off Jbar stays 1;
//  R3 with F-bar, Newton still converges quadratically in plastic steps (the strip load);
//  R4 fbar = true is refused for small-strain laws;
//  R5 drop_weak_nodes removes a node a point reaches by a sliver, and only such nodes;
//  R6 the rank partition of a distributed run (mpm/PointPartition.hpp) gives every point
//     to exactly one rank, keeps the points of each F-bar cell on one rank (their
//     averaged volume change is formed there), and balances the counts to within a cell;
//     and in the rigid footing the MPI tests run (examples/footing_rigid_2d.toml to
//     s/B = 0.09 on 2 and 3 ranks) points do change rank during the run, so those tests
//     cover points crossing rank boundaries.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <map>

#include "MpmTestUtil.hpp"
#include "PlasticityTestUtil.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/mpm/LoadStep.hpp"
#include "gradmpm/mpm/PointPartition.hpp"
#include "gradmpm/mpm/RankPoints.hpp"

using namespace gradmpm;

namespace {
const char* kBlock = R"(
[grid]
origin = [-0.25, -0.25]
cell_size = 0.25
cells = [6, 6]
[basis]
type = "gimp"
[mpm]
fbar = true
[materials.clay]
model = "von-mises"
young = 1000.0
poisson = 0.3
yield_stress = 2.0
hardening = 30.0
[[bodies]]
material = "clay"
min = [0.0, 0.0]
max = [1.0, 1.0]
[[constraints]]
min = [-0.25, -0.25]
max = [1.25, 0.0]
fix = ["x", "y"]
[[constraints]]
min = [0.0, 1.0]
max = [0.25, 1.0]
fix = ["y"]
displacement = [0.0, -0.05]
[load_steps]
count = 4
[output]
vtk_every = 0
)";
}  // namespace

TEST(FBar, TangentIsTheDerivativeOfTheInternalForce) {
  for (bool fbar : {true, false}) {
    CaseFile cf =
        CaseFile::parse(kBlock, "block.toml", {fbar ? "mpm.fbar=true" : "mpm.fbar=false", "load_steps.count=1"});
    MpmCase<2> c = read_mpm_case<2>(cf);
    run_quasi_static<2>(c.model, c.newton);  // a plastic, moved state (GIMP stencils of 3x3 nodes)
    detail::LoadStep<2> step(c.model, 1.0, 0.1);
    const int n = step.dofs().num_dofs();
    const test::TangentCheck check = test::assembled_tangent_check(step, 0.004, 7, 1e-7);
    int plastic = 0;  // points that yield in this iterate
    for (int p = 0; p < c.model.points.size(); ++p) plastic += c.model.points.state_of(p)[6] > 0.0;
    const double rel = check.error, asym = check.asymmetry;
    std::cout << (fbar ? "F-bar" : "standard") << ": " << n << " dofs, " << plastic
              << " yielded points, max |K - K_fd| / max |K| = " << rel << ", asymmetry " << asym << "\n";
    EXPECT_GT(plastic, 0);
    EXPECT_LT(rel, 1e-6) << (fbar ? "F-bar" : "standard");
    if (fbar) EXPECT_GT(asym, 1e-6) << "the F-bar tangent is not symmetric";
  }
}

TEST(FBar, ThePointsOfACellShareOneVolumeChange) {
  CaseFile one = CaseFile::parse(kBlock, "block.toml", {"load_steps.count=1"});
  MpmCase<2> s = read_mpm_case<2>(one);
  const std::vector<Vec<2>> x0 = s.model.points.position;
  run_quasi_static<2>(s.model, s.newton);
  const auto& P = s.model.points;
  double spread = 0.0, dev = 0.0;
  for (int p = 0; p < P.size(); ++p)
    for (int q = 0; q < P.size(); ++q)
      if (*s.model.grid.cell_of(x0[p]) == *s.model.grid.cell_of(x0[q]))
        spread = std::max(spread, std::abs(P.fbar_jacobian[p] - P.fbar_jacobian[q]));
  for (int p = 0; p < P.size(); ++p) dev = std::max(dev, std::abs(P.fbar_jacobian[p] - 1.0));
  std::cout << "Jbar after one step: spread within a cell " << spread << ", largest change " << dev << "\n";
  EXPECT_LT(spread, 1e-14);
  EXPECT_GT(dev, 1e-5) << "volumes did change";
  CaseFile off = CaseFile::parse(kBlock, "block.toml", {"load_steps.count=1", "mpm.fbar=false"});
  MpmCase<2> o = read_mpm_case<2>(off);
  run_quasi_static<2>(o.model, o.newton);
  for (double j : o.model.points.fbar_jacobian) EXPECT_EQ(j, 1.0);
}

TEST(FBar, NewtonConvergesQuadraticallyInPlasticSteps) {
  // The strip load of test_plasticity.cpp (8 x 8 cells, von Mises, H = 50) with F-bar.
  CaseFile cf = CaseFile::parse(test::strip_load_case(), "strip.toml", {"mpm.fbar=true"});
  MpmCase<2> c = read_mpm_case<2>(cf);
  ASSERT_TRUE(c.model.fbar);
  test::QuadraticRate rate;
  run_quasi_static<2>(c.model, c.newton, [&](const Model<2>&, const StepInfo& info) { rate.add(info.residuals); });
  std::cout << "F-bar strip load: worst log-ratio " << rate.worst << " over " << rate.checked << " iterations\n";
  EXPECT_GT(rate.checked, 5);
  EXPECT_GE(rate.worst, 1.8);
}

TEST(FBar, IsRefusedForSmallStrainLaws) {
  CaseFile cf =
      CaseFile::parse(kBlock, "block.toml", {"materials.clay.model=linear-elastic", "materials.clay.yield_stress=1"});
  EXPECT_THROW(read_mpm_case<2>(cf), InputError);
  const std::string refused = test::read_error<2>(CaseFile::parse(
      "[grid]\norigin=[0.0,0.0]\ncell_size=1.0\ncells=[2,2]\n[mpm]\nfbar=true\n[materials.a]\nmodel=\"linear-"
      "elastic\"\nyoung=1.0\n"
      "[[bodies]]\nmaterial=\"a\"\nmin=[0.0,0.0]\nmax=[1.0,1.0]\n[load_steps]\ncount=1\n",
      "small.toml"));
  EXPECT_NE(refused.find("mpm.fbar: expected false with the small-strain model \"linear-elastic\""), std::string::npos)
      << refused;
}

TEST(FBar, WeakNodesAreDroppedAndOnlyThem) {
  // 1D, cells of 1: a uGIMP point whose domain [0.25, 1.0 + 1e-6] reaches node 2 (support
  // [1, 3]) by a sliver; a second point well inside cell 1 keeps node 2 strong in the
  // second grid.
  Grid<1> grid(Vec<1>(0.0), Vec<1>(1.0), {3});
  MaterialPoints<1> pts;
  pts.add(Vec<1>(0.625 + 0.5e-6), 0.375, 0, Vec<1>(0.375 + 0.5e-6));
  auto st = evaluate_stencils(grid, pts, BasisKind::UGIMP);
  int touches_node2 = 0;
  for (int a = 0; a < st[0].count; ++a) touches_node2 += st[0].node[a] == 2;
  ASSERT_EQ(touches_node2, 1) << "the sliver reaches node 2";
  EXPECT_EQ(drop_weak_nodes(st, pts, grid.num_nodes(), 1.0, 1e-8), 1);
  double sum = 0.0;
  for (int a = 0; a < st[0].count; ++a) {
    EXPECT_NE(st[0].node[a], 2);
    sum += st[0].N[a];
  }
  EXPECT_NEAR(sum, 1.0, 1e-8) << "the partition of unity is kept to the threshold";
  pts.add(Vec<1>(1.5), 0.5, 0, Vec<1>(0.25));
  auto st2 = evaluate_stencils(grid, pts, BasisKind::UGIMP);
  EXPECT_EQ(drop_weak_nodes(st2, pts, grid.num_nodes(), 1.0, 1e-8), 0) << "node 2 is strong now";
}

TEST(FBar, RankPartitionKeepsEachCellOnOneRank) {
  // Requirement: a distributed run's load step gives each rank whole F-bar cells (points
  // coupled through their averaged volume change), every point to one rank, and ranks of
  // nearly equal point counts in the reference configuration: the boxes are cut at whole
  // layers of cells (grid/RankBoxes.hpp), so within a layer of an even share, and no
  // rank empty while the layers across the cut outnumber the ranks (4 x 4 cells here: on
  // 5 ranks one box is empty).
  CaseFile cf = CaseFile::parse(kBlock, "block.toml", {"load_steps.count=2"});
  MpmCase<2> c = read_mpm_case<2>(cf);
  run_quasi_static<2>(c.model, c.newton);  // moved points: GIMP stencils of 2 to 3 nodes a side
  const auto& P = c.model.points;
  const PointStencils<2> st = evaluate_stencils(c.model.grid, P, c.model.basis);
  const FBarCells<2> cells(c.model.grid, P, st);
  std::map<int, int> group;  // points per cell in the reference configuration: a cut moves on by less than one
  for (int k : cell_corner_keys(c.model.grid, P.original_position)) ++group[k];
  int largest_group = 0;
  for (const auto& [k, n] : group) largest_group = std::max(largest_group, n);
  int largest_layer = 0;  // points in a layer of cells, in either direction
  for (int d = 0; d < 2; ++d) {
    std::map<int, int> layer;
    for (const auto& [k, n] : group) layer[c.model.grid.node_ijk(k)[d]] += n;
    for (const auto& [i, n] : layer) largest_layer = std::max(largest_layer, n);
  }
  for (int ranks : {2, 3, 5}) {
    const PointPartition part = points_of_ranks(c.model.grid, P.original_position, P.position, ranks);
    std::vector<int> rank_of(P.size(), -1);
    for (int r = 0; r < ranks; ++r)
      for (const int* p = part.begin(r); p != part.end(r); ++p) {
        EXPECT_EQ(rank_of[*p], -1) << "point " << *p << " given twice";
        rank_of[*p] = r;
      }
    for (int p = 0; p < P.size(); ++p) EXPECT_GE(rank_of[p], 0) << "point " << p << " given to no rank";
    for (const auto& m : cells.members())
      for (int q : m) EXPECT_EQ(rank_of[q], rank_of[m.front()]) << ranks << " ranks: a cell split";
    const PointPartition start = points_of_ranks(c.model.grid, P.original_position, P.original_position, ranks);
    int fewest = P.size(), most = 0;
    for (int r = 0; r < ranks; ++r) fewest = std::min(fewest, start.count(r)), most = std::max(most, start.count(r));
    std::cout << ranks << " ranks: " << fewest << " to " << most << " points at the start (largest cell group "
              << largest_group << ", largest layer " << largest_layer << ")\n";
    EXPECT_LE(most, (P.size() + ranks - 1) / ranks + largest_layer) << ranks << " ranks";
    if (ranks < 5) EXPECT_GT(fewest, 0) << ranks << " ranks";
  }
}

/// The settings of Mpi.PlasticColumn3d* (tests/CMakeLists.txt): the Hencky column of
/// the MPI tests made von Mises, yielding under its weight below about mid-height.
const std::vector<std::string> kPlasticColumn = {"materials.soil.model=von-mises", "materials.soil.yield_stress=5.0"};

/// How often a point's rank (points_of_ranks after each load step on 2 and 3 ranks: the rank that owns it)
/// changes from one load step to the next over a run of `file`.
template <int dim>
std::array<int, 2> rank_changes(const std::string& file, const std::vector<std::string>& sets) {
  CaseFile cf = CaseFile::load(std::string(GRADMPM_SOURCE_DIR) + file, sets);
  MpmCase<dim> c = read_mpm_case<dim>(cf);
  auto ranks_of = [&](int ranks) {
    const PointPartition part =
        points_of_ranks(c.model.grid, c.model.points.original_position, c.model.points.position, ranks);
    std::vector<int> rank_of(c.model.points.size());
    for (int r = 0; r < ranks; ++r)
      for (const int* p = part.begin(r); p != part.end(r); ++p) rank_of[*p] = r;
    return rank_of;
  };
  std::array<std::vector<int>, 2> last{ranks_of(2), ranks_of(3)};
  std::array<int, 2> changes{0, 0};
  run_quasi_static<dim>(c.model, c.newton, [&](const Model<dim>&, const StepInfo&) {
    for (int k = 0; k < 2; ++k) {
      const std::vector<int> now = ranks_of(k + 2);
      for (int p = 0; p < c.model.points.size(); ++p) changes[k] += now[p] != last[k][p];
      last[k] = now;
    }
  });
  std::cout << file << ": changes of rank over the run: " << changes[0] << " on 2 ranks, " << changes[1]
            << " on 3 ranks\n";
  return changes;
}

TEST(FBar, PointsOfTheMpiTestCasesChangeRankDuringTheRun) {
  // Requirement: an elasto-plastic MPI test case whose points cross rank
  // boundaries during the run. The footings' points under the footing move less than a
  // quarter cell at the cuts (mid-depth); the 3D column settles under its weight by
  // about half a cell at mid-height, so its points cross into the lower rank's cells.
  const auto node_row =
      rank_changes<2>("/examples/footing_tresca_2d.toml", {"output.vtk_every=0", "output.plot=false"});
  EXPECT_EQ(node_row[0] + node_row[1], 0) << "if this changes, the Tresca MPI tests cover crossings too";
  const auto column = rank_changes<3>("/tests/mpi/column_3d_gradient.toml", kPlasticColumn);
  EXPECT_GT(column[0], 0) << "2 ranks";
  EXPECT_GT(column[1], 0) << "3 ranks";
}
