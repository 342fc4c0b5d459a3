// Requirement (docs/parallel.md): a distributed run cuts the grid into
// boxes of cells, one per rank, laid out as PETSc's DMDA lays out a structured grid
// (grid/RankBoxes.hpp). Every cell and every node has exactly one owner, whose box holds
// it; the cut balances the points, and among balanced arrays of ranks takes the one whose
// cuts cross the least of the body (boxes, not slabs, when the ranks are many).
#include <gtest/gtest.h>

#include <set>

#include "gradmpm/grid/RankBoxes.hpp"

using namespace gradmpm;

namespace {

/// Counts per node (x fastest) of a grid of `cells`, with `per_cell` points in each cell
/// of the box [lo, hi) of cells.
std::vector<long long> body(const std::vector<int>& cells, std::array<int, 3> lo, std::array<int, 3> hi,
                            long long per_cell = 4) {
  std::array<int, 3> size{1, 1, 1};
  for (std::size_t d = 0; d < cells.size(); ++d) size[d] = cells[d] + 1;
  std::vector<long long> count(static_cast<std::size_t>(size[0]) * size[1] * size[2], 0);
  for (int k = lo[2]; k < hi[2]; ++k)
    for (int j = lo[1]; j < hi[1]; ++j)
      for (int i = lo[0]; i < hi[0]; ++i) count[i + size[0] * (j + size[1] * k)] = per_cell;
  return count;
}

std::vector<int> ranks_across(const RankBoxes& b) {
  std::vector<int> m;
  for (int d = 0; d < b.dim(); ++d) m.push_back(static_cast<int>(b.cut(d).size()) - 1);
  return m;
}

}  // namespace

TEST(RankBoxes, EveryCellAndNodeHasOneOwnerWhoseBoxHoldsIt) {
  // 5 x 4 x 3 cells, 2 x 2 x 1 ranks with uneven ranges (rank r = i + 2 j, as DMDA's).
  const std::vector<int> cells = {5, 4, 3};
  const RankBoxes b(cells, {{0, 2, 5}, {0, 1, 4}, {0, 3}});
  ASSERT_EQ(b.size(), 4);
  ASSERT_EQ(b.num_nodes(), 6 * 5 * 4);
  const RankBoxes::Box box1 = b.box(1);
  EXPECT_EQ(box1.lo, (std::array<int, 3>{2, 0, 0}));
  EXPECT_EQ(box1.hi, (std::array<int, 3>{5, 1, 3}));
  std::vector<int> node_visits(b.num_nodes(), 0), cell_visits(b.num_nodes(), 0);
  for (int r = 0; r < 4; ++r) {
    int previous = -1;
    b.for_each_node(r, [&](int n) {
      EXPECT_GT(n, previous) << "ascending";
      previous = n;
      EXPECT_EQ(b.owner(n), r) << "node " << n;
      ++node_visits[n];
    });
    const RankBoxes::Box box = b.box(r);
    b.for_each_cell(r, [&](int key) {
      EXPECT_EQ(b.owner(key), r);
      const int i = key % 6, j = key / 6 % 5, k = key / 30;
      EXPECT_TRUE(i >= box.lo[0] && i < box.hi[0] && j >= box.lo[1] && j < box.hi[1] && k >= box.lo[2] && k < box.hi[2]);
      ++cell_visits[key];
    });
  }
  int keys = 0;
  for (int n = 0; n < b.num_nodes(); ++n) {
    EXPECT_EQ(node_visits[n], 1) << "node " << n;
    const int i = n % 6, j = n / 6 % 5, k = n / 30;
    const bool key = i < 5 && j < 4 && k < 3;
    keys += key;
    EXPECT_EQ(cell_visits[n], key ? 1 : 0) << "node " << n;
  }
  EXPECT_EQ(keys, 5 * 4 * 3);
  // A node on the grid's upper faces belongs to the last cell below it: (5, 4, 3) to rank 3.
  EXPECT_EQ(b.owner(5 + 6 * (4 + 5 * 3)), 3);
  EXPECT_EQ(b.owner(5 + 6 * 0), 1);
  // near(): within the layers of the box's corner nodes (rank 0: nodes i 0..2, j 0..1).
  EXPECT_TRUE(b.near(0, 3 + 6 * 2, 1));
  EXPECT_FALSE(b.near(0, 4 + 6 * 2, 1));
  EXPECT_FALSE(b.near(0, 3 + 6 * 3, 1));
  EXPECT_TRUE(b.near(0, 4 + 6 * 3, 2));
}

// The numbering by owners visits only the nodes near a rank's box (DofMap): those must be
// exactly the nodes near() accepts, ascending, for every rank and width (an empty box's too).
TEST(RankBoxes, TheNodesNearABoxAreVisitedOnceAscendingAndNoOthers) {
  const RankBoxes boxes3(std::vector<int>{5, 4, 3}, {{0, 2, 5}, {0, 1, 4}, {0, 3}});
  const RankBoxes boxes2(std::vector<int>{4, 2}, {{0, 2, 2, 4}, {0, 2}});  // rank 1's box has no cells
  for (const RankBoxes* b : {&boxes3, &boxes2})
    for (int r = 0; r < b->size(); ++r)
      for (int layers : {0, 1, 2, 7}) {
        std::vector<int> visited;
        b->for_each_node_near(r, layers, [&](int n) { visited.push_back(n); });
        std::vector<int> expected;
        for (int n = 0; n < b->num_nodes(); ++n)
          if (b->near(r, n, layers)) expected.push_back(n);
        EXPECT_FALSE(visited.empty());
        EXPECT_EQ(visited, expected) << b->dim() << "D, rank " << r << ", " << layers << " layer(s)";
      }
}

TEST(RankBoxes, ASquareBodyOnFourRanksIsCutIntoFourEqualBoxesAndOnTwoIntoSlabs) {
  // A 10 x 10 block of cells in a 20 x 20 grid: 2 x 2 boxes of 25 cells (cuts surface 20
  // cells against 30 for four slabs, both balanced); on two ranks one cut of the slowest
  // axis (the cuts of either axis equal).
  const std::vector<int> cells = {20, 20};
  const std::vector<long long> count = body(cells, {5, 5, 0}, {15, 15, 1});
  const RankBoxes four = RankBoxes::of_counts(cells, count, 4);
  EXPECT_EQ(four.cut(0), (std::vector<int>{0, 10, 20}));
  EXPECT_EQ(four.cut(1), (std::vector<int>{0, 10, 20}));
  std::vector<long long> held(4, 0);
  for (int n = 0; n < four.num_nodes(); ++n) held[four.owner(n)] += count[n];
  EXPECT_EQ(held, (std::vector<long long>{100, 100, 100, 100}));
  const RankBoxes two = RankBoxes::of_counts(cells, count, 2);
  EXPECT_EQ(ranks_across(two), (std::vector<int>{1, 2}));
  EXPECT_EQ(two.cut(1), (std::vector<int>{0, 10, 20}));
}

TEST(RankBoxes, TheArrayOfRanksFollowsTheBodysShape) {
  // A column 4 cells wide and 40 tall: slabs on 2 to 5 ranks (a cut across the width
  // crosses 4 cells, along the height 40).
  const std::vector<int> column = {6, 42};
  for (int ranks = 2; ranks <= 5; ++ranks)
    EXPECT_EQ(ranks_across(RankBoxes::of_counts(column, body(column, {1, 1, 0}, {5, 41, 1}), ranks)),
              (std::vector<int>{1, ranks}))
        << ranks << " ranks";
  // A layer 40 cells long and 10 deep on 4 ranks: four cuts across the length (surface 30)
  // rather than 2 x 2 (surface 50).
  const std::vector<int> layer = {40, 10};
  EXPECT_EQ(ranks_across(RankBoxes::of_counts(layer, body(layer, {0, 0, 0}, {40, 10, 1}), 4)),
            (std::vector<int>{4, 1}));
  // A cube of 12^3 cells: 8 ranks as 2 x 2 x 2, 12 as 2 x 2 x 3 (the three on the slowest
  // axis when the surfaces tie), each box holding 1/8 or 1/12 of the points.
  const std::vector<int> cube = {12, 12, 12};
  const std::vector<long long> count = body(cube, {0, 0, 0}, {12, 12, 12}, 1);
  EXPECT_EQ(ranks_across(RankBoxes::of_counts(cube, count, 8)), (std::vector<int>{2, 2, 2}));
  const RankBoxes twelve = RankBoxes::of_counts(cube, count, 12);
  EXPECT_EQ(ranks_across(twelve), (std::vector<int>{2, 2, 3}));
  std::vector<long long> held(12, 0);
  for (int n = 0; n < twelve.num_nodes(); ++n) held[twelve.owner(n)] += count[n];
  for (int r = 0; r < 12; ++r) EXPECT_EQ(held[r], 12 * 12 * 12 / 12) << "rank " << r;
  // One dimension: three runs of a bar's 9 cells at equal counts.
  const RankBoxes bar = RankBoxes::of_counts({9}, body({9}, {0, 0, 0}, {9, 1, 1}), 3);
  EXPECT_EQ(bar.cut(0), (std::vector<int>{0, 3, 6, 9}));
}

TEST(RankBoxes, AnUnevenBodyKeepsItsBalanceBeforeItsSurface) {
  // An L: a 20 x 4 foot and a 4 x 16 leg above its left end (80 + 64 cells of 4 points).
  // On 4 ranks, 2 x 2 boxes (the least surface) hold 64, 256, 256 and 0 points at best;
  // four slabs either way hold at most 160 (two of the foot's 80-point rows or columns:
  // a cut moves on past a layer's points), so four slabs it is, across the slowest axis
  // as the surfaces tie (3 x 20 cells).
  const std::vector<int> cells = {20, 20};
  std::vector<long long> count = body(cells, {0, 0, 0}, {20, 4, 1});
  const std::vector<long long> leg = body(cells, {0, 4, 0}, {4, 20, 1});
  for (std::size_t n = 0; n < count.size(); ++n) count[n] += leg[n];
  const RankBoxes b = RankBoxes::of_counts(cells, count, 4);
  EXPECT_EQ(ranks_across(b), (std::vector<int>{1, 4}));
  std::vector<long long> held(4, 0);
  for (int n = 0; n < b.num_nodes(); ++n) held[b.owner(n)] += count[n];
  EXPECT_EQ(*std::max_element(held.begin(), held.end()), 160);
  EXPECT_EQ(std::set<long long>(held.begin(), held.end()).count(0), 0u) << "no empty box";
}
