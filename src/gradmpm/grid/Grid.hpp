#pragma once
// The regular background grid of the MPM (paper, section 1): origin, cell size and
// cell counts per direction. It never deforms; after each load step it is "reset",
// which for a regular grid simply means the nodal fields are discarded.
//
// Node numbering is lexicographic with x fastest: n = i + (nx+1) * (j + (ny+1) * k).
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "gradmpm/core/Types.hpp"

namespace gradmpm {

template <int dim>
class Grid {
 public:
  using Index = std::array<int, dim>;

  Grid(const Vec<dim>& origin, const Vec<dim>& cell_size, const Index& cells)
      : origin_(origin), h_(cell_size), cells_(cells) {
    // Counted in 64 bits: node and cell numbers are ints, so a larger grid is refused here
    // (case files are checked with a message before: app/MpmCaseReader.cpp).
    long long nodes = 1, cells_total = 1;
    for (int d = 0; d < dim; ++d) {
      nodes *= static_cast<long long>(cells_[d]) + 1;
      cells_total *= cells_[d];
      if (cells_[d] < 1 || nodes > std::numeric_limits<int>::max())
        throw std::length_error("Grid: the node count does not fit in an int");
    }
    num_nodes_ = static_cast<int>(nodes);
    num_cells_ = static_cast<int>(cells_total);
  }

  const Vec<dim>& origin() const { return origin_; }
  const Vec<dim>& cell_size() const { return h_; }
  const Index& cells() const { return cells_; }
  int num_nodes() const { return num_nodes_; }
  int num_cells() const { return num_cells_; }
  double cell_volume() const { return h_.prod(); }

  int node_index(const Index& ijk) const {
    int n = 0;
    for (int d = dim - 1; d >= 0; --d) n = n * (cells_[d] + 1) + ijk[d];
    return n;
  }

  Index node_ijk(int n) const {
    Index ijk{};
    for (int d = 0; d < dim; ++d) {
      ijk[d] = n % (cells_[d] + 1);
      n /= cells_[d] + 1;
    }
    return ijk;
  }

  /// Whether node n is a cell's lower corner (a cell's key): not on the grid's upper faces.
  bool is_cell_key(int n) const {
    const Index ijk = node_ijk(n);
    for (int d = 0; d < dim; ++d)
      if (ijk[d] >= cells_[d]) return false;
    return true;
  }

  Vec<dim> node_position(int n) const {
    const Index ijk = node_ijk(n);
    Vec<dim> x;
    for (int d = 0; d < dim; ++d) x[d] = origin_[d] + ijk[d] * h_[d];
    return x;
  }

  /// Cell holding x; a point on the upper face of the grid belongs to the last cell.
  /// Returns nothing for points outside the grid.
  std::optional<Index> cell_of(const Vec<dim>& x) const {
    Index c{};
    for (int d = 0; d < dim; ++d) {
      const double xi = (x[d] - origin_[d]) / h_[d];
      if (!(xi >= 0.0) || xi > cells_[d]) return std::nullopt;  // also rejects NaN
      c[d] = std::min(static_cast<int>(std::floor(xi)), cells_[d] - 1);
    }
    return c;
  }

 private:
  Vec<dim> origin_;
  Vec<dim> h_;
  Index cells_;
  int num_nodes_ = 0;
  int num_cells_ = 0;
};

}  // namespace gradmpm
