// Requirement (no grid-sized collective in a load step, docs/parallel.md): the
// per-node sums made before a step's numbering exists (F-bar's node supports, the
// regularisation's weak-node diagonal) are summed at the nodes' owners with neighbour
// messages (grid/NodeSums.hpp), and give every rank the sum over the ranks at each node it
// owns or touches, as the all-reduce of the whole grid did; elsewhere a rank keeps its own
// part. Integer-valued parts, so the sums are exact whatever their order.
// Run: mpirun -n N node_sums_check (exit 0: every check held).
// The grid (9 x 8 x 5 cells) is cut by RankBoxes::of_counts for a uniform body (2 x 2 x 1
// boxes on 4 ranks); each rank touches the nodes of its box but every fifth, the nodes of a
// layer beyond each side, and a few far away.
#include <cstdio>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/grid/NodeSums.hpp"

using namespace gradmpm;

int main(int argc, char** argv) {
  ranks::Session session(&argc, &argv);
  const int size = ranks::size(), me = ranks::rank();
  const std::vector<int> cells = {9, 8, 5};
  const int nx = 10, ny = 9, nz = 6, num_nodes = nx * ny * nz;
  std::vector<long long> per_node(num_nodes, 0);
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 9; ++i) per_node[i + nx * (j + ny * k)] = 1;
  const RankBoxes boxes = RankBoxes::of_counts(cells, per_node, size);
  const RankBoxes::Box box = boxes.box(me);
  std::vector<double> part(num_nodes, 0.0);
  std::vector<char> touched(num_nodes, 0);
  auto touch = [&](int n) {
    touched[n] = 1;
    part[n] = static_cast<double>((n * 7 + me * 13) % 11 + 1);
  };
  int k = 0;
  boxes.for_each_node(me, [&](int n) {
    if (k++ % 5 != 0) touch(n);
  });
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const bool near = x >= box.lo[0] - 1 && x <= box.hi[0] + 1 && y >= box.lo[1] - 1 && y <= box.hi[1] + 1 &&
                          z >= box.lo[2] - 1 && z <= box.hi[2] + 1;
        if (near) touch(x + nx * (y + ny * z));
      }
  touch((box.lo[0] + nx * box.lo[1] + 211) % num_nodes);
  touch((37 * me + 5) % num_nodes);
  std::vector<double> whole = part;
  ranks::sum(whole.data(), whole.size());
  Paged<double> summed(num_nodes, 0.0);  // (as the callers hold it: pages near the touched nodes)
  std::vector<int> touched_nodes;
  for (int n = 0; n < num_nodes; ++n)
    if (touched[n]) {
      summed.set(n, part[n]);
      touched_nodes.push_back(n);
    }
  sum_at_owners(boxes, summed, touched_nodes);
  int failures = 0, exact = 0;
  for (int n = 0; n < num_nodes; ++n) {
    const bool total = touched[n] || boxes.owner(n) == me;
    const double expected = total ? whole[n] : part[n];
    exact += total;
    if (summed[n] != expected && failures++ < 10)
      std::fprintf(stderr, "rank %d, node %d: %g, expected %g\n", me, n, summed[n], expected);
  }
  ranks::max(&failures, 1);
  if (me == 0)
    std::printf("%d ranks: rank 0 holds the totals at %d of %d nodes: %s\n", size, exact, num_nodes,
                failures ? "FAILED" : "the whole grid's sums");
  return failures ? 1 : 0;
}
