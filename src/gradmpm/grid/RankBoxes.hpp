#pragma once
// A distributed run's partition of the background grid into boxes of cells, one per
// rank, laid out as PETSc's DMDA lays out a structured grid (DMDASetOwnershipRanges): the
// ranks form an m_0 x m_1 (x m_2) array, direction d is cut at its own cell indices
// 0 = cut[d][0] <= ... <= cut[d][m_d] = cells[d], and rank r = i_0 + m_0 (i_1 + m_1 i_2)
// owns the cells [cut[0][i_0], cut[0][i_0 + 1]) x [cut[1][i_1], cut[1][i_1 + 1]) x ...
// A slab is the box of an array with one rank across the other directions.
//
// A node belongs to the rank of the cell it is the lower corner of (a node on the grid's
// upper faces to the rank of the last cell below it), so a cell's key (its lower-corner
// node, cell_corner_key) and a node are looked up alike (owner()).
//
// The cut is made once, from the points' counts per cell in the reference configuration
// (of_counts): each direction at nearly equal counts of its layers of cells, and the
// array of ranks chosen for the least cut surface (the body's cross-sections the cuts
// cross) among the arrays whose fullest box holds at most 5 % more points than the
// fullest box of the best-balanced array. A slab's surface does not shrink as the ranks
// grow in number; a box's does (docs/parallel.md).
#include <algorithm>
#include <array>
#include <stdexcept>
#include <vector>

namespace gradmpm {

/// The cut of n layers holding per_layer[i] points each into `parts` runs of layers at
/// nearly equal counts: run p is layers [first[p], first[p + 1]) (parts + 1 entries,
/// from 0 to n). A cut that falls inside a layer's points moves on past them.
inline std::vector<int> cut_at_counts(const std::vector<long long>& per_layer, int parts) {
  const int n = static_cast<int>(per_layer.size());
  std::vector<long long> before(n + 1, 0);  // points of layers < i
  for (int i = 0; i < n; ++i) before[i + 1] = before[i] + per_layer[i];
  const long long np = before[n];
  std::vector<int> first(parts + 1, n);
  first[0] = 0;
  long long previous = 0;
  for (int p = 1; p < parts; ++p) {
    long long cut = std::max(previous, np * p / parts);
    int i = static_cast<int>(std::upper_bound(before.begin(), before.end(), cut) - before.begin()) - 1;
    if (cut > 0 && cut < np && cut > before[i]) cut = before[i + 1];
    previous = cut;
    if (cut < np) first[p] = static_cast<int>(std::upper_bound(before.begin(), before.end(), cut) - before.begin()) - 1;
  }
  return first;
}

class RankBoxes {
 public:
  /// Cells [lo[d], hi[d]) in each direction (directions beyond the grid's: [0, 1)).
  struct Box {
    std::array<int, 3> lo{0, 0, 0}, hi{1, 1, 1};
    bool empty() const { return lo[0] >= hi[0] || lo[1] >= hi[1] || lo[2] >= hi[2]; }
  };

  /// No partition: a serial run (every rank holds every point).
  RankBoxes() = default;

  /// `cells`: the grid's cells per direction; `cuts[d]`: m_d + 1 cell indices from 0 to
  /// cells[d], ascending (see the header).
  RankBoxes(std::vector<int> cells, std::vector<std::vector<int>> cuts) : cells_(std::move(cells)), cuts_(std::move(cuts)) {
    if (cells_.empty() || cells_.size() > 3 || cuts_.size() != cells_.size())
      throw std::logic_error("RankBoxes: one cut per direction of a 1D, 2D or 3D grid");
    part_.resize(cells_.size());
    for (std::size_t d = 0; d < cells_.size(); ++d) {
      const std::vector<int>& c = cuts_[d];
      if (c.size() < 2 || c.front() != 0 || c.back() != cells_[d] || !std::is_sorted(c.begin(), c.end()))
        throw std::logic_error("RankBoxes: a direction's cut must run from 0 to its cells, ascending");
      part_[d].resize(cells_[d]);
      for (int p = 0; p + 1 < static_cast<int>(c.size()); ++p)
        for (int i = c[p]; i < c[p + 1]; ++i) part_[d][i] = p;
    }
  }

  /// The partition of a grid of `cells` per direction whose keys (node indices, x
  /// fastest) hold per_node[n] points each, for `ranks` ranks (see the header).
  static RankBoxes of_counts(const std::vector<int>& cells, const std::vector<long long>& per_node, int ranks) {
    const int dim = static_cast<int>(cells.size());
    std::vector<std::vector<long long>> per_layer(dim);
    for (int d = 0; d < dim; ++d) per_layer[d].assign(cells[d], 0);
    // The counts summed over the cells below each node (a summed-area table on the nodes'
    // lattice: below[n] holds the points of the cells [0, i) x [0, j) x [0, k) for node
    // (i, j, k)), so that any box's points are 2^dim lookups.
    std::array<long long, 3> size{1, 1, 1};
    for (int d = 0; d < dim; ++d) size[d] = cells[d] + 1;
    std::vector<long long> below(per_node.size(), 0);
    for (long long n = 0; n < static_cast<long long>(per_node.size()); ++n) {
      if (per_node[n] == 0) continue;
      long long rest = n, up = 0, stride = 1;
      for (int d = 0; d < dim; ++d) {
        const int i = static_cast<int>(rest % size[d]);
        rest /= size[d];
        per_layer[d][std::min(i, cells[d] - 1)] += per_node[n];
        up += stride * (std::min(i, cells[d] - 1) + 1);  // the node above the cell in every direction
        stride *= size[d];
      }
      below[up] += per_node[n];
    }
    for (int d = 0, stride = 1; d < dim; stride *= static_cast<int>(size[d]), ++d)
      for (long long n = 0; n < static_cast<long long>(below.size()); ++n)
        if ((n / stride) % size[d] > 0) below[n] += below[n - stride];
    auto points_in = [&](const Box& b) {
      long long sum = 0;
      for (int corner = 0; corner < (1 << dim); ++corner) {
        long long n = 0, stride = 1;
        int lows = 0;
        for (int d = 0; d < dim; ++d) {
          const bool low = !((corner >> d) & 1);
          lows += low;
          n += stride * (low ? b.lo[d] : b.hi[d]);
          stride *= size[d];
        }
        sum += lows % 2 ? -below[n] : below[n];
      }
      return sum;
    };
    // The body's extent in cells along each direction (for the cut surface).
    std::vector<double> extent(dim);
    for (int d = 0; d < dim; ++d) {
      int low = cells[d], high = -1;
      for (int i = 0; i < cells[d]; ++i)
        if (per_layer[d][i] > 0) low = std::min(low, i), high = i;
      extent[d] = high >= low ? high - low + 1 : cells[d];
    }
    // Every array of ranks m_0 x ... = ranks, each scored by its fullest box and surface.
    struct Candidate {
      RankBoxes boxes;
      long long fullest;
      double surface;
      std::vector<int> m;
    };
    std::vector<Candidate> candidates;
    std::vector<int> m(dim, 1);
    auto score = [&]() {
      std::vector<std::vector<int>> cuts(dim);
      for (int d = 0; d < dim; ++d) cuts[d] = cut_at_counts(per_layer[d], m[d]);
      RankBoxes boxes(cells, cuts);
      long long fullest = 0;
      for (int r = 0; r < ranks; ++r) fullest = std::max(fullest, points_in(boxes.box(r)));
      double surface = 0.0;
      for (int d = 0; d < dim; ++d) {
        double across = m[d] - 1;
        for (int e = 0; e < dim; ++e)
          if (e != d) across *= extent[e];
        surface += across;
      }
      candidates.push_back({std::move(boxes), fullest, surface, m});
    };
    auto arrays = [&](auto&& self, int d, int left) -> void {
      if (d == dim - 1) {
        m[d] = left;
        score();
        return;
      }
      for (int k = 1; k <= left; ++k)
        if (left % k == 0) {
          m[d] = k;
          self(self, d + 1, left / k);
        }
    };
    arrays(arrays, 0, ranks);
    long long best = candidates.front().fullest;
    for (const Candidate& c : candidates) best = std::min(best, c.fullest);
    const Candidate* chosen = nullptr;
    for (const Candidate& c : candidates) {
      if (c.fullest > best + best / 20) continue;
      // Least surface; equal surfaces: more ranks across the slower directions (slabs
      // across the slowest axis, as a run of cells in their numbering).
      if (!chosen || c.surface < chosen->surface ||
          (c.surface == chosen->surface &&
           std::lexicographical_compare(chosen->m.rbegin(), chosen->m.rend(), c.m.rbegin(), c.m.rend())))
        chosen = &c;
    }
    return chosen->boxes;
  }

  bool empty() const { return cuts_.empty(); }
  int dim() const { return static_cast<int>(cells_.size()); }
  const std::vector<int>& cells() const { return cells_; }
  /// Direction d's cut (ranks across it + 1 entries).
  const std::vector<int>& cut(int d) const { return cuts_[d]; }
  /// The number of ranks (boxes).
  int size() const {
    int n = 1;
    for (const auto& c : cuts_) n *= static_cast<int>(c.size()) - 1;
    return n;
  }
  /// The number of grid nodes.
  int num_nodes() const {
    int n = 1;
    for (int c : cells_) n *= c + 1;
    return n;
  }

  /// The rank that owns node n, or the cell whose lower corner n is (see the header).
  int owner(int n) const {
    int r = 0, stride = 1;
    for (int d = 0; d < dim(); ++d) {
      const int i = n % (cells_[d] + 1);
      n /= cells_[d] + 1;
      r += stride * part_[d][std::min(i, cells_[d] - 1)];
      stride *= static_cast<int>(cuts_[d].size()) - 1;
    }
    return r;
  }

  /// Rank r's cells.
  Box box(int r) const {
    Box b;
    for (int d = 0; d < dim(); ++d) {
      const int m = static_cast<int>(cuts_[d].size()) - 1, i = r % m;
      r /= m;
      b.lo[d] = cuts_[d][i];
      b.hi[d] = cuts_[d][i + 1];
    }
    return b;
  }

  /// Whether node n lies within `layers` node layers of rank r's box (of the corners of
  /// its cells) in every direction.
  bool near(int r, int n, int layers) const {
    const Box b = box(r);
    for (int d = 0; d < dim(); ++d) {
      const int i = n % (cells_[d] + 1);
      n /= cells_[d] + 1;
      if (i < b.lo[d] - layers || i > b.hi[d] + layers) return false;
    }
    return true;
  }

  /// Calls f(n) for each node n with near(r, n, layers), ascending: the nodes of rank r's
  /// box widened by `layers` node layers, within the grid (an empty box too, as near()).
  template <class F>
  void for_each_node_near(int r, int layers, F&& f) const {
    Box b = box(r);
    std::array<int, 3> size{1, 1, 1};
    for (int d = 0; d < dim(); ++d) {
      size[d] = cells_[d] + 1;
      b.lo[d] = std::max(0, b.lo[d] - layers);
      b.hi[d] = std::min(cells_[d], b.hi[d] + layers) + 1;  // (near() includes hi + layers)
    }
    for (int k = b.lo[2]; k < b.hi[2]; ++k)
      for (int j = b.lo[1]; j < b.hi[1]; ++j)
        for (int i = b.lo[0]; i < b.hi[0]; ++i) f(i + size[0] * (j + size[1] * k));
  }

  /// Calls f(key) for the lower-corner node of each of rank r's cells, ascending.
  template <class F>
  void for_each_cell(int r, F&& f) const {
    visit(box(r), false, f);
  }

  /// Calls f(n) for each node rank r owns (owner(n) == r), ascending.
  template <class F>
  void for_each_node(int r, F&& f) const {
    visit(box(r), true, f);
  }

 private:
  /// The node indices of box b's cells' lower corners, ascending; with `faces`, also
  /// the nodes on the grid's upper faces the box reaches.
  template <class F>
  void visit(Box b, bool faces, F&& f) const {
    if (b.empty()) return;
    std::array<int, 3> size{1, 1, 1};
    for (int d = 0; d < dim(); ++d) {
      size[d] = cells_[d] + 1;
      if (faces && b.hi[d] == cells_[d]) ++b.hi[d];
    }
    for (int k = b.lo[2]; k < b.hi[2]; ++k)
      for (int j = b.lo[1]; j < b.hi[1]; ++j)
        for (int i = b.lo[0]; i < b.hi[0]; ++i) f(i + size[0] * (j + size[1] * k));
  }

  std::vector<int> cells_;
  std::vector<std::vector<int>> cuts_;
  std::vector<std::vector<int>> part_;  ///< part_[d][i]: the index, across direction d, of layer i's run
};

}  // namespace gradmpm
