// Requirement (issue 14, stage 4b): a distributed run's points travel between ranks with
// every per-point array, their state and their ids, and a rank's points are listed in
// increasing id whichever way they came (mpm/PointMigration.hpp). The exchange itself is
// MPI's (the Mpi.* tests run it on 2 and 3 ranks against the serial answer); here, on one
// rank, the bookkeeping around it: the order the received rows are put in, rows of every
// width (4-byte integers, 3x3 matrices, state blocks of several values a point), and the
// points a rank keeps.
#include <gtest/gtest.h>

#include <numeric>
#include <string>
#include <type_traits>

#include "MpmTestUtil.hpp"
#include "gradmpm/mpm/PointMigration.hpp"
#include "gradmpm/mpm/RankPoints.hpp"

using namespace gradmpm;
using namespace gradmpm::test;

TEST(PointMigration, ReceivedPointsAreListedInIncreasingIdWithEveryArray) {
  // Four points held in the order of ids 5, 2, 9, 0 (as a rank receives them from others):
  // after the exchange (every point to this rank) every array follows the ids' order.
  const std::vector<int> ids = {5, 2, 9, 0};
  std::vector<int> material = {50, 20, 90, 0};
  std::vector<double> volume = {5.5, 2.5, 9.5, 0.5};
  std::vector<Vec<3>> x = {Vec<3>(5, 5.1, 5.2), Vec<3>(2, 2.1, 2.2), Vec<3>(9, 9.1, 9.2), Vec<3>(0, 0.1, 0.2)};
  std::vector<Mat3> F(4);
  for (int p = 0; p < 4; ++p) F[p] = Mat3::Constant(ids[p]) + Mat3::Identity() * 0.25;
  std::vector<double> state(4 * 3);  // three values a point
  for (int p = 0; p < 4; ++p)
    for (int k = 0; k < 3; ++k) state[p * 3 + k] = 10.0 * ids[p] + k;
  std::vector<int> moved_ids = ids;

  const PointMigration m = PointMigration::exchange(std::vector<int>(4, 0), ids);
  EXPECT_EQ(m.ids(), (std::vector<int>{0, 2, 5, 9}));
  EXPECT_EQ(m.sent(), 0) << "nothing left this rank";
  m.apply(material);
  m.apply(volume);
  m.apply(x);
  m.apply(F);
  m.apply(state, 3);
  m.apply(moved_ids);
  EXPECT_EQ(moved_ids, m.ids());
  EXPECT_EQ(material, (std::vector<int>{0, 20, 50, 90}));
  EXPECT_EQ(volume, (std::vector<double>{0.5, 2.5, 5.5, 9.5}));
  for (int p = 0; p < 4; ++p) {
    const int id = m.ids()[p];
    EXPECT_EQ(x[p], Vec<3>(id, id + 0.1, id + 0.2)) << "point " << id;
    EXPECT_EQ(F[p], Mat3(Mat3::Constant(id) + Mat3::Identity() * 0.25)) << "point " << id;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(state[p * 3 + k], 10.0 * id + k) << "point " << id;
  }
}

TEST(PointMigration, KeptPointsOfAModelAreItsSubsetWithTheirIds) {
  // A rank that holds every point keeps its own: every array, the state block and the ids
  // are those of MaterialPoints::subset (written independently), and Model::id_of names them.
  Model<2> m = make_column<2>(6, BasisKind::MPM);
  m.initialise_state();
  for (int p = 0; p < m.points.size(); ++p) {  // distinct values in every array
    m.points.work[p] = 0.5 * p;
    m.points.stress[p] = Mat3::Constant(p);
    m.points.force[p] = Vec<2>(p, -p);
  }
  const std::vector<int> mine = {1, 4, 5, 10};
  const MaterialPoints<2> expected = m.points.subset(mine);
  migrate_points(m, PointMigration::keep(mine));
  EXPECT_EQ(m.point_ids, mine);
  ASSERT_EQ(m.points.size(), 4);
  for (int p = 0; p < 4; ++p) EXPECT_EQ(m.id_of(p), mine[p]);
  int arrays = 0;
  m.points.for_each_array([&](const char* name, const auto& a) {
    ++arrays;
    expected.for_each_array([&](const char* other, const auto& b) {
      if constexpr (std::is_same_v<std::decay_t<decltype(a)>, std::decay_t<decltype(b)>>)
        if (std::string(name) == other) EXPECT_TRUE(a == b) << name;
    });
  });
  EXPECT_EQ(arrays, 13);
  EXPECT_EQ(m.points.state, expected.state);
}

TEST(RankPoints, EachPointHasOneOwnerAndTheCutIsFixedByTheReferenceConfiguration) {
  // owners(): the rank of each point's current cell under the cut of the reference
  // positions; a point moved down by a cell at a cut belongs to the rank below.
  Model<2> m = make_column<2>(12, BasisKind::MPM);
  m.rank_cells = rank_cells(m.grid, m.points.original_position, 3);
  ASSERT_EQ(m.rank_cells.size(), 4u);
  EXPECT_EQ(m.rank_cells.front(), 0);
  EXPECT_EQ(m.rank_cells.back(), m.grid.num_nodes());
  std::vector<int> count(3, 0);
  for (const int r : owners(m)) ++count[r];
  EXPECT_EQ(count, (std::vector<int>{16, 16, 16})) << "12 cells of 4 points, cut at equal counts";
  // Move rank 1's lowest points (its first cell row, the grid's 6th: cells of rank 0 are
  // rows 2 to 5, the first row below the column being empty) down by one cell.
  const double h = m.grid.cell_size()[1];
  const std::vector<int> before = owners(m);
  int moved = 0;
  for (int p = 0; p < m.points.size(); ++p)
    if (before[p] == 1 && m.points.position[p][1] < m.grid.origin()[1] + 6.0 * h) {
      m.points.position[p][1] -= h;
      ++moved;
    }
  ASSERT_GT(moved, 0);
  const std::vector<int> after = owners(m);
  int changed = 0;
  for (int p = 0; p < m.points.size(); ++p) changed += after[p] != before[p];
  EXPECT_EQ(changed, moved);
  EXPECT_EQ(rank_cells(m.grid, m.points.original_position, 3), m.rank_cells) << "the cut does not move";
}

TEST(RankPoints, TheCutFromCountsIsTheCutOfThePointsSortedByKey) {
  // rank_cells_of_counts (the reader's, from counts per cell without making the points)
  // and partition_points (the points sorted by key, cut at equal counts, moved on past the
  // rest of a key) give each rank the same first cell, on uneven keys with empty ones.
  std::vector<int> key;
  const int num_keys = 40;
  unsigned seed = 7;
  for (int p = 0; p < 500; ++p) {
    seed = seed * 1103515245u + 12345u;
    const int k = static_cast<int>((seed >> 16) % num_keys);
    if (k % 7 != 3) key.push_back(k);  // some keys without points
  }
  std::vector<long long> per_key(num_keys, 0);
  for (const int k : key) ++per_key[k];
  for (int ranks = 2; ranks <= 9; ++ranks) {
    const PointPartition part = partition_points(key, num_keys, ranks);
    std::vector<int> first(ranks + 1, num_keys);
    first[0] = 0;
    for (int r = 1; r < ranks; ++r)
      if (part.start[r] < static_cast<int>(key.size())) first[r] = key[part.order[part.start[r]]];
    EXPECT_EQ(rank_cells_of_counts(per_key, ranks), first) << ranks << " ranks";
  }
}

TEST(RankPoints, EachRankOwnsTheEquationsOfTheNodesOfItsCells) {
  // Grid partition, step 1 (docs/parallel.md): rank r owns the equations of the active
  // nodes in its run of the cut (DofMap::rows_of, the rows PETSc gives it), a contiguous
  // block after the ranks before it; the nodes of a rank's points' own cells (their lower
  // corners, the keys) are in its rows, so its share of the tangent falls there but for
  // the nodes its points reach across the cut.
  for (const BasisKind basis : {BasisKind::MPM, BasisKind::CPGIMP}) {
    const Model<2> m = make_column<2>(12, basis);
    const auto st = evaluate_stencils(m.grid, m.points, basis);
    const DofMap dofs(st, m.grid.num_nodes(), 2);
    for (int ranks = 1; ranks <= 5; ++ranks) {
      const std::vector<int> cut = rank_cells(m.grid, m.points.original_position, ranks);
      const std::vector<int> rows = dofs.rows_of(cut);
      ASSERT_EQ(rows.size(), cut.size());
      EXPECT_EQ(rows.front(), 0);
      EXPECT_EQ(rows.back(), dofs.num_dofs());
      for (int e = 0; e < dofs.num_dofs(); ++e) {
        const int node = dofs.node_of(e / 2), r = owner_of(cut, node);
        EXPECT_TRUE(e >= rows[r] && e < rows[r + 1]) << "equation " << e << " of node " << node << ", " << ranks << " ranks";
      }
      // The ghost layer: a point's stencil nodes outside its rank's rows lie at most one
      // node row below the rank's lowest cells (GIMP's support; none for MPM) and one
      // (MPM) or two (GIMP) above its highest (the upper corners of its top cells).
      const std::vector<int> owner = owners(m.grid, cut, m.points.position);
      std::vector<int> low(ranks, 1 << 30), high(ranks, -1);  // each rank's points' cell rows
      for (int p = 0; p < m.points.size(); ++p) {
        const int row = m.grid.node_ijk(cell_corner_key(m.grid, m.points.position[p]))[1];
        low[owner[p]] = std::min(low[owner[p]], row);
        high[owner[p]] = std::max(high[owner[p]], row);
      }
      const int below = basis == BasisKind::MPM ? 0 : 1, above = basis == BasisKind::MPM ? 1 : 2;
      int ghosts = 0;
      for (int p = 0; p < m.points.size(); ++p) {
        const int key = cell_corner_key(m.grid, m.points.position[p]), r = owner[p];
        ASSERT_TRUE(dofs.active(key));
        EXPECT_GE(dofs.dof(key, 0), rows[r]);
        EXPECT_LT(dofs.dof(key, 1), rows[r + 1]);
        for (int a = 0; a < st[p].count; ++a) {
          const int node = st[p].node[a], e = dofs.dof(node, 0);
          if (e >= rows[r] && e < rows[r + 1]) continue;
          ++ghosts;
          const int row = m.grid.node_ijk(node)[1];
          EXPECT_TRUE(row >= low[r] - below && row <= high[r] + above) << "node " << node << " of a point of rank " << r;
        }
      }
      if (ranks == 1) EXPECT_EQ(ghosts, 0);
      else EXPECT_GT(ghosts, 0);
    }
  }
}
