// Requirement (issue 14, grid partition, docs/parallel.md): a distributed run's load step
// numbers its equations by the nodes' owners (DofMap with a margin: neighbour messages,
// no all-reduce over the grid) and every rank gets the numbering of the union over the
// ranks (DofMap::every_node) wherever it looks: the same equation for each node it knows,
// the same rows per rank; it knows every node it owns, every node its stencils reach
// (wherever they are) and the nodes within the margin of its run, and no others.
// Run: mpirun -n N dof_map_check (exit 0: every check held).
// Each rank's stencils reach nodes in its run and a few far away (a stretched GIMP
// domain), and some nodes of every run are reached by no rank (inactive).
#include <cstdio>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/solver/DofMap.hpp"

using namespace gradmpm;

int main(int argc, char** argv) {
  ranks::Session session(&argc, &argv);
  const int size = ranks::size(), me = ranks::rank(), num_nodes = 601, margin = 7;
  int failures = 0;
  auto fail = [&](const char* what, int node, int got, int expected) {
    if (failures++ < 10) std::fprintf(stderr, "rank %d: %s, node %d: %d, expected %d\n", me, what, node, got, expected);
  };
  std::vector<int> cut(size + 1, 0);  // uneven runs
  for (int r = 1; r < size; ++r) cut[r] = static_cast<int>(1LL * num_nodes * r * r / (size * size));
  cut[size] = num_nodes;
  // This rank's stencils: every third node of its run (so some nodes are nobody's), the
  // first nodes of the next run, and two nodes far away.
  PointStencils<2> st;
  auto reach = [&](int node) {
    Stencil<2> s;
    s.count = 1;
    s.node[0] = node;
    st.push_back(s);
  };
  for (int n = cut[me]; n < cut[me + 1]; n += 3) reach(n);
  for (int n = cut[me + 1]; n < std::min(num_nodes, cut[me + 1] + 4); ++n) reach(n);
  reach((cut[me] + 300) % num_nodes);
  reach((7 * me + 11) % num_nodes);
  const DofMap whole(st, num_nodes, 2, cut, DofMap::every_node);
  const DofMap by_owners(st, num_nodes, 2, cut, margin);
  if (whole.rank_rows() != by_owners.rank_rows()) fail("rank rows differ", -1, 0, 0);
  if (whole.num_dofs() != by_owners.num_dofs()) fail("equations", -1, by_owners.num_dofs(), whole.num_dofs());
  std::vector<char> reached(num_nodes, 0);
  for (const auto& s : st) reached[s.node[0]] = 1;
  int known = 0;
  for (int n = 0; n < num_nodes; ++n) {
    const bool own = n >= cut[me] && n < cut[me + 1];
    const bool near = n >= cut[me] - margin && n < cut[me + 1] + margin;
    const bool should_know = whole.active(n) && (own || near || reached[n]);
    if (by_owners.active(n) != should_know) fail("known", n, by_owners.active(n), should_know);
    if (should_know && by_owners.dof(n, 1) != whole.dof(n, 1)) fail("equation", n, by_owners.dof(n, 1), whole.dof(n, 1));
    if (by_owners.active(n) && by_owners.node_of(by_owners.dof(n, 0) / 2) != n) fail("node_of", n, -1, n);
    known += by_owners.active(n);
  }
  if (size > 2 && known >= whole.num_active_nodes()) fail("knows every active node", -1, known, whole.num_active_nodes());
  int failed = failures;
  ranks::max(&failed, 1);
  if (me == 0)
    std::printf("%d ranks: rank 0 knows %d of %d active nodes, the union's equations: %s\n", size, known,
                whole.num_active_nodes(), failed ? "FAILED" : "the same");
  return failed ? 1 : 0;
}
