// Requirement: a distributed run's points travel between ranks with
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
    m.points.velocity[p] = Vec<2>(2 * p, p);
    m.points.acceleration[p] = Vec<2>(-p, 3 * p);
    m.points.pore_pressure[p] = 7.0 * p;
    m.points.contact_shear[p] = Vec<2>(3 * p, -2 * p);
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
  EXPECT_EQ(arrays, 17);
  EXPECT_EQ(m.points.state, expected.state);
}

TEST(RankPoints, EachPointHasOneOwnerAndTheCutIsFixedByTheReferenceConfiguration) {
  // owners(): the rank of each point's current cell under the cut of the reference
  // positions; a point moved down by a cell at a cut belongs to the rank below.
  Model<2> m = make_column<2>(12, BasisKind::MPM);
  m.rank_boxes = rank_boxes(m.grid, m.points.original_position, 3);
  ASSERT_EQ(m.rank_boxes.size(), 3);
  EXPECT_EQ(m.rank_boxes.cut(0), (std::vector<int>{0, 1})) << "a column one cell wide: slabs";
  EXPECT_EQ(m.rank_boxes.cut(1).front(), 0);
  EXPECT_EQ(m.rank_boxes.cut(1).back(), m.grid.cells()[1]);
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
  EXPECT_EQ(rank_boxes(m.grid, m.points.original_position, 3).cut(1), m.rank_boxes.cut(1)) << "the cut does not move";
}

TEST(RankPoints, TheCutFromCountsIsTheCutOfThePointsSortedByKey) {
  // cut_at_counts (each direction's cut, from counts per layer of cells without making
  // the points) and partition_points (the points sorted by key, cut at equal counts,
  // moved on past the rest of a key) give each part the same first layer, on uneven
  // layers with empty ones.
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
    EXPECT_EQ(cut_at_counts(per_key, ranks), first) << ranks << " ranks";
  }
}

TEST(RankPoints, APointsStencilReachesOneNodeLayerBeyondItsRanksBox) {
  // The ghost layer of the partition (docs/parallel.md): a point's stencil nodes that
  // another rank owns lie at most one node row below the rank's lowest cells (GIMP's
  // support; none for MPM) and one (MPM) or two (GIMP) above its highest (the upper
  // corners of its top cells), and a point's own cell's lower corner is its rank's.
  for (const BasisKind basis : {BasisKind::MPM, BasisKind::CPGIMP}) {
    const Model<2> m = make_column<2>(12, basis);
    const auto st = evaluate_stencils(m.grid, m.points, basis);
    for (int ranks = 1; ranks <= 5; ++ranks) {
      const RankBoxes boxes = rank_boxes(m.grid, m.points.original_position, ranks);
      ASSERT_EQ(boxes.size(), ranks);
      const std::vector<int> owner = owners(m.grid, boxes, m.points.position);
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
        EXPECT_EQ(boxes.owner(key), r);
        for (int a = 0; a < st[p].count; ++a) {
          const int node = st[p].node[a];
          if (boxes.owner(node) == r) continue;
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
