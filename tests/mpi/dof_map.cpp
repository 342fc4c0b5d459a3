// Requirement (docs/parallel.md): a distributed run's load step
// numbers its equations by the nodes' owners (DofMap with a margin: neighbour messages,
// no all-reduce over the grid) and every rank gets the numbering of the union over the
// ranks (DofMap::every_node) wherever it looks: the same equation for each node it knows,
// the same rows per rank, each rank's own nodes a run of equations in increasing index;
// it knows every node it owns, every node its stencils reach (wherever they are) and the
// nodes within the margin of its box, and no others; its equations are local (its vectors
// hold the nodes it knows only): its own nodes first, as its run of global rows, then the
// others by increasing global equation, global_rows() mapping each to the union's.
// Run: mpirun -n N dof_map_check (exit 0: every check held).
// The grid (24 x 24 cells) is cut into uneven boxes (2 x 2 on 4 ranks, 3 x 1 on 3);
// each rank's stencils reach nodes in its box, the next node layers beyond it in x and
// y, and a few far away (a stretched GIMP domain), and some nodes of every box are
// reached by no rank (inactive).
#include <cstdio>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/solver/DofMap.hpp"

using namespace gradmpm;

int main(int argc, char** argv) {
  ranks::Session session(&argc, &argv);
  const int size = ranks::size(), me = ranks::rank(), num_nodes = 25 * 25, margin = 2;
  int failures = 0;
  auto fail = [&](const char* what, int node, int got, int expected) {
    if (failures++ < 10) std::fprintf(stderr, "rank %d: %s, node %d: %d, expected %d\n", me, what, node, got, expected);
  };
  // Uneven cuts: ranks across x and y (4 = 2 x 2, 3 = 3 x 1, 2 = 1 x 2).
  const int across_x = size == 2 ? 1 : (size % 2 == 0 ? 2 : size), across_y = size / across_x;
  auto uneven = [](int parts) {
    std::vector<int> c(parts + 1, 24);
    for (int p = 0; p < parts; ++p) c[p] = 24 * p * p / (parts * parts);
    return c;
  };
  const RankBoxes boxes({24, 24}, {uneven(across_x), uneven(across_y)});
  // This rank's stencils: every third node of its box (so some nodes are nobody's), the
  // two node layers beyond its box's upper sides, and two nodes far away.
  PointStencils<2> st;
  auto reach = [&](int node) {
    Stencil<2> s;
    s.count = 1;
    s.node[0] = node;
    st.push_back(s);
  };
  int k = 0;
  boxes.for_each_node(me, [&](int n) {
    if (k++ % 3 == 0) reach(n);
  });
  const RankBoxes::Box box = boxes.box(me);
  for (int j = box.lo[1]; j <= std::min(24, box.hi[1] + 1); ++j)
    for (int i = box.lo[0]; i <= std::min(24, box.hi[0] + 1); ++i)
      if (i > box.hi[0] || j > box.hi[1]) reach(i + 25 * j);
  reach((box.lo[0] + 25 * box.lo[1] + 300) % num_nodes);
  reach((7 * me + 11) % num_nodes);
  const DofMap whole(st, num_nodes, 2, boxes, DofMap::every_node);
  const DofMap by_owners(st, num_nodes, 2, boxes, margin);
  if (whole.rank_rows() != by_owners.rank_rows()) fail("rank rows differ", -1, 0, 0);
  if (whole.num_dofs() != by_owners.num_global_dofs())
    fail("equations", -1, by_owners.num_global_dofs(), whole.num_dofs());
  int previous = -1;  // this rank's own nodes: its rows, ascending
  boxes.for_each_node(me, [&](int n) {
    if (!whole.active(n)) return;
    const int e = whole.dof(n, 0);
    if (e < whole.rank_rows()[me] || e >= whole.rank_rows()[me + 1] || e <= previous) fail("own row", n, e, previous + 2);
    previous = e;
  });
  std::vector<char> reached(num_nodes, 0);
  for (const auto& s : st) reached[s.node[0]] = 1;
  int known = 0;
  for (int n = 0; n < num_nodes; ++n) {
    const bool own = boxes.owner(n) == me;
    const bool near = boxes.near(me, n, margin);
    const bool should_know = whole.active(n) && (own || near || reached[n]);
    if (by_owners.active(n) != should_know) fail("known", n, by_owners.active(n), should_know);
    if (should_know && by_owners.global_dof(n, 1) != whole.dof(n, 1))
      fail("equation", n, by_owners.global_dof(n, 1), whole.dof(n, 1));
    if (by_owners.active(n) && by_owners.node_of(by_owners.dof(n, 0) / 2) != n) fail("node_of", n, -1, n);
    if (by_owners.active(n) && own != (by_owners.dof(n, 0) / 2 < by_owners.own_nodes_last()))
      fail("own nodes first", n, by_owners.dof(n, 0), by_owners.own_nodes_last() * 2);
    known += by_owners.active(n);
  }
  // Local equations: exactly the known nodes; global_rows() is the union's numbering, own
  // rows first as this rank's run, the others ascending.
  if (by_owners.num_active_nodes() != known) fail("local nodes", -1, by_owners.num_active_nodes(), known);
  const std::vector<int> rows = by_owners.global_rows();
  if (size > 1 && static_cast<int>(rows.size()) != by_owners.num_dofs())
    fail("global rows", -1, static_cast<int>(rows.size()), by_owners.num_dofs());
  for (int row = 0; size > 1 && row < static_cast<int>(rows.size()); ++row) {
    const int node = by_owners.node_of(row / 2);
    if (rows[row] != whole.dof(node, row % 2)) fail("global row", node, rows[row], whole.dof(node, row % 2));
    const bool own_row = row < by_owners.own_nodes_last() * 2;
    if (own_row && rows[row] != whole.rank_rows()[me] + row) fail("own run", node, rows[row], whole.rank_rows()[me] + row);
    if (!own_row && row > by_owners.own_nodes_last() * 2 && rows[row] <= rows[row - 1])
      fail("others ascending", node, rows[row], rows[row - 1] + 1);
  }
  if (size > 2 && known >= whole.num_active_nodes()) fail("knows every active node", -1, known, whole.num_active_nodes());
  int failed = failures;
  ranks::max(&failed, 1);
  if (me == 0)
    std::printf("%d ranks: rank 0 knows %d of %d active nodes, the union's equations: %s\n", size, known,
                whole.num_active_nodes(), failed ? "FAILED" : "the same");
  return failed ? 1 : 0;
}
