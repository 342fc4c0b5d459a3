// bench_partition: how the grid's cut into ranks' boxes (grid/RankBoxes.hpp) grows with
// the ranks, against slabs across the slowest axis, for a block that fills the grid
// (docs/parallel.md, "Boxes against slabs"). Never part of the tests; no MPI: the cut
// is made as every rank makes it, for P ranks at a time.
//
//   build/bench/bench_partition [--cells N] [--dim 2|3] [--ranks P1,P2,...]
//
// For each P: the array of ranks chosen, the points of the fullest box against an even
// share (every cell holds 8 points), and a rank's ghost nodes: the nodes its points'
// stencils reach that other ranks own, counted geometrically for GIMP supports of moved
// points (one node layer below a box's cells and two above, in each direction: the
// ghost layer RankPoints.APointsStencilReachesOneNodeLayerBeyondItsRanksBox checks), the
// most of any rank and against the nodes it owns. The ghost nodes are what each Newton
// iteration sends and receives (f_int's and the solution's ghost rows, dim values each).
// Also the seconds RankBoxes::of_counts takes (every rank makes the cut once per run).
// With more ranks than layers of cells, slabs leave ranks empty (the fullest slab then
// holds a layer: the "fullest" column grows as P / layers).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "gradmpm/grid/RankBoxes.hpp"

using namespace gradmpm;

namespace {

struct Figures {
  long long fullest = 0, ghosts = 0, owned = 0;  // the rank with the most ghost nodes: its own nodes
};

Figures measure(const RankBoxes& b, const std::vector<int>& cells, long long per_cell) {
  Figures f;
  const int dim = b.dim();
  for (int r = 0; r < b.size(); ++r) {
    const RankBoxes::Box box = b.box(r);
    if (box.empty()) continue;  // (no points, no stencils)
    long long held = per_cell, reach = 1, own = 1;
    for (int d = 0; d < dim; ++d) {
      held *= box.hi[d] - box.lo[d];
      // Nodes reached: from one layer below its cells to two above (clipped to the grid);
      // nodes owned: its cells' lower corners, and the grid's upper face where it ends there.
      const int lo = std::max(0, box.lo[d] - 1), hi = std::min(cells[d], box.hi[d] + 1);
      reach *= hi - lo + 1;
      own *= box.hi[d] - box.lo[d] + (box.hi[d] == cells[d] ? 1 : 0);
    }
    f.fullest = std::max(f.fullest, held);
    if (reach - own > f.ghosts) f.ghosts = reach - own, f.owned = own;
  }
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  int n = 100, dim = 3;
  std::vector<int> ranks = {2, 4, 8, 16, 32, 64, 128, 256, 512, 1024};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--cells" && i + 1 < argc) n = std::atoi(argv[++i]);
    else if (a == "--dim" && i + 1 < argc) dim = std::atoi(argv[++i]);
    else if (a == "--ranks" && i + 1 < argc) {
      ranks.clear();
      std::stringstream s(argv[++i]);
      for (std::string p; std::getline(s, p, ',');) ranks.push_back(std::atoi(p.c_str()));
    } else {
      fmt::print(stderr, "bench_partition: unknown argument {} (expected --cells N, --dim 2|3, --ranks P1,P2,...)\n", a);
      return 2;
    }
  }
  if (n < 2 || (dim != 2 && dim != 3)) {
    fmt::print(stderr, "bench_partition: --cells must be at least 2 and --dim 2 or 3\n");
    return 2;
  }
  const std::vector<int> cells(dim, n);
  const long long per_cell = dim == 2 ? 4 : 8;  // 2 points per cell and direction
  long long nodes = 1, points = per_cell;
  for (int d = 0; d < dim; ++d) nodes *= n + 1, points *= n;
  std::vector<long long> per_node(nodes, 0);
  for (long long k = 0; k < nodes; ++k) {
    long long rest = k;
    bool key = true;
    for (int d = 0; d < dim; ++d, rest /= n + 1) key = key && rest % (n + 1) < n;
    if (key) per_node[k] = per_cell;
  }
  fmt::print("{}D block of {}^{} cells, {} nodes ({} dof), {} points\n", dim, n, dim, nodes, nodes * dim, points);
  fmt::print("{:>6} | {:>12} {:>8} {:>9} {:>10} {:>7} | {:>8} {:>9} {:>10} {:>7}\n", "ranks", "boxes", "cut s",
             "fullest", "ghosts", "/own", "slabs", "fullest", "ghosts", "/own");
  for (const int P : ranks) {
    const auto start = std::chrono::steady_clock::now();
    const RankBoxes boxes = RankBoxes::of_counts(cells, per_node, P);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::vector<std::vector<int>> slab_cuts;
    for (int d = 0; d < dim; ++d) slab_cuts.push_back(d + 1 < dim ? std::vector<int>{0, n} : std::vector<int>{});
    std::vector<long long> per_layer(n, points / n);
    slab_cuts[dim - 1] = cut_at_counts(per_layer, P);
    const RankBoxes slabs(cells, slab_cuts);
    const Figures b = measure(boxes, cells, per_cell), s = measure(slabs, cells, per_cell);
    std::string across;
    for (int d = 0; d < dim; ++d) across += (d ? "x" : "") + std::to_string(boxes.cut(d).size() - 1);
    const double even = static_cast<double>(points) / P;
    fmt::print("{:>6} | {:>12} {:>8.3f} {:>9.3f} {:>10} {:>7.3f} | {:>8} {:>9.3f} {:>10} {:>7.3f}\n", P, across, seconds,
               b.fullest / even, b.ghosts, static_cast<double>(b.ghosts) / b.owned, fmt::format("1x..x{}", P),
               s.fullest / even, s.ghosts, s.owned ? static_cast<double>(s.ghosts) / s.owned : 0.0);
  }
  return 0;
}
