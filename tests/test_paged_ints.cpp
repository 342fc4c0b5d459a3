// Requirement (docs/parallel.md): a rank's
// node-to-equation map (DofMap) holds memory only near the nodes it knows, not an
// integer per grid node, and reads as before: PagedInts reads the default wherever
// nothing else was written, keeps every value written, allocates a page only on the
// first write of another value there, and copies whole.
#include <gtest/gtest.h>

#include <vector>

#include "gradmpm/core/PagedInts.hpp"
#include "gradmpm/points/Transfer.hpp"
#include "gradmpm/solver/DofMap.hpp"

using namespace gradmpm;

TEST(PagedInts, ReadsTheDefaultAndTheWrittenValuesAndHoldsOnlyWrittenPages) {
  const int n = 10 * PagedInts::page_size + 7;  // a partial last page
  PagedInts a(n, -1);
  EXPECT_EQ(a.bytes(), 0u);
  for (const int i : {0, n - 1, 5 * PagedInts::page_size + 3}) EXPECT_EQ(a[i], -1) << i;
  a.set(3 * PagedInts::page_size + 1, -1);  // the default: nothing allocated
  EXPECT_EQ(a.bytes(), 0u);
  a.set(3 * PagedInts::page_size + 1, 42);
  a.set(3 * PagedInts::page_size + 2, 43);
  a.set(n - 1, 7);
  EXPECT_EQ(a.bytes(), 2u * PagedInts::page_size * sizeof(int));  // two pages of eleven
  EXPECT_EQ(a[3 * PagedInts::page_size + 1], 42);
  EXPECT_EQ(a[3 * PagedInts::page_size + 2], 43);
  EXPECT_EQ(a[3 * PagedInts::page_size], -1);
  EXPECT_EQ(a[n - 1], 7);
  EXPECT_EQ(a[2 * PagedInts::page_size + 1], -1);
  PagedInts b = a;  // a copy has its own pages
  a.set(n - 1, 8);
  EXPECT_EQ(b[n - 1], 7);
  EXPECT_EQ(b[3 * PagedInts::page_size + 2], 43);
  EXPECT_EQ(b.bytes(), a.bytes());
  PagedInts c = std::move(b);  // a move keeps them
  EXPECT_EQ(c[n - 1], 7);
  EXPECT_EQ(c[3 * PagedInts::page_size + 1], 42);
}

// for_each_held visits the allocated pages' entries only, ascending, and none beyond
// size() (the last page is partial): the numbering's and the regularisation's walk.
TEST(PagedInts, ForEachHeldVisitsTheAllocatedPagesEntriesInOrder) {
  const int n = 10 * PagedInts::page_size + 7;
  PagedInts a(n, -1);
  a.set(n - 1, 7);
  a.set(3 * PagedInts::page_size + 2, 43);
  std::vector<int> seen;
  long set = 0;
  a.for_each_held([&](int i, int v) {
    seen.push_back(i);
    if (v != -1) set += static_cast<long>(i) * v;
  });
  ASSERT_EQ(seen.size(), static_cast<std::size_t>(PagedInts::page_size + 7));  // page 3 and the last page's 7
  EXPECT_EQ(seen.front(), 3 * PagedInts::page_size);
  EXPECT_EQ(seen[PagedInts::page_size - 1], 4 * PagedInts::page_size - 1);
  EXPECT_EQ(seen[PagedInts::page_size], 10 * PagedInts::page_size);
  EXPECT_EQ(seen.back(), n - 1);
  EXPECT_EQ(set, 43L * (3 * PagedInts::page_size + 2) + 7L * (n - 1));
}

TEST(PagedInts, ADofMapOfAFewStencilsOnALargeGridHoldsAFewPages) {
  // A 1000 x 1000-node grid whose stencils reach a 10 x 10 block of nodes: numbered as
  // in increasing index, with 3 pages (the block's 10 node rows are 1000 apart) where an
  // integer per grid node is 4 MB.
  const int side = 1000;
  PointStencils<2> st;
  for (int j = 500; j < 510; ++j)
    for (int i = 200; i < 210; ++i) {
      Stencil<2> s;
      s.count = 1;
      s.node[0] = i + side * j;
      st.push_back(s);
    }
  const DofMap dofs(st, side * side, 2);
  EXPECT_EQ(dofs.num_active_nodes(), 100);
  EXPECT_EQ(dofs.num_grid_nodes(), side * side);
  EXPECT_EQ(dofs.node_map_bytes(), 3u * PagedInts::page_size * sizeof(int));  // nodes 500200 to 509209
  int e = 0;
  for (int j = 500; j < 510; ++j)
    for (int i = 200; i < 210; ++i, ++e) {
      EXPECT_EQ(dofs.dof(i + side * j, 1), 2 * e + 1);
      EXPECT_EQ(dofs.node_of(e), i + side * j);
    }
  EXPECT_FALSE(dofs.active(0));
  EXPECT_FALSE(dofs.active(side * side - 1));
  EXPECT_FALSE(dofs.active(199 + side * 500));
}
