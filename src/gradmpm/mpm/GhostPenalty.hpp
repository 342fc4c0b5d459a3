#pragma once
// Ghost stabilisation of the implicit MPM against the small-cut instability (Burman 2010,
// "Ghost penalty", C. R. Acad. Sci. Paris I 348; for the MPM: Coombs 2023, "Ghost
// stabilisation of the Material Point Method for stable quasi-static and dynamic analysis
// of large deformation problems", IJNME 124). A grid node reached by points only through
// a sliver of their support has almost no stiffness; with perfect plasticity (and F-bar
// handing its volumetric stiffness to the cell) the tangent turns singular there
// (docs/plasticity.md). The penalty ties such nodes to their neighbours by penalising the
// jump of the normal derivative of the load step's displacement increment across the
// faces of the boundary cells,
//   G(du, dv) = sum_F gamma_F h ∫_F [[d du / dn]] . [[d dv / dn]] dF,   gamma_F = alpha E_F,
// E_F the largest Young's modulus of the points in the face's two cells. It vanishes for
// every displacement field linear across the face (consistent to first order), adds
// f += G du to the internal force and G to the tangent (symmetric).
//
// For the grid's multilinear basis, across the face x_d = x_k between cells L and R,
// [[dN_a/dn]] = c_a / h_d T_a(y) with c = (1, -2, 1) for the node planes k-1, k, k+1 and T_a
// the node's tangential hat functions, so the face matrix is
//   g_ab = gamma / h_d c_a c_b prod_{e != d} h_e m(a_e, b_e),  m = 1/3 (same), 1/6 (other).
// Which faces: those shared by two active cells (every node active: the cell overlaps some
// point's support, as a cut cell does in CutFEM), at least one of them empty of points:
// the cells a body's points reach only through the edge of their supports. Faces between
// cells that hold points are never penalised, so the plastic zone under a load is not
// stiffened (penalising the faces of every cell beside an empty one raised the Tresca
// footing's collapse load by 10 % at alpha = 0.01: measured, docs/plasticity.md).
// Axisymmetric (r-z, x the radius): the face integrals are per radian, weighted by r as
// every other term is: a face r = r_F takes r_F, and a face z = const integrates
// T_a T_b r dr over its extent in r > 0 (two-point Gauss, exact for the cubic).
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/grid/Grid.hpp"
#include "gradmpm/grid/RankBoxes.hpp"
#include "gradmpm/materials/Material.hpp"
#include "gradmpm/points/MaterialPoints.hpp"
#include "gradmpm/solver/SparsePattern.hpp"

namespace gradmpm {

template <int dim>
class GhostFaces {
 public:
  static constexpr int kFaceNodes = 3 * (1 << (dim - 1));
  struct Face {
    int count = 0;                                    ///< its active nodes
    int normal = 0;                                   ///< the direction d of the face x_d = const
    std::array<int, kFaceNodes> node{};               ///< grid node numbers
    std::array<double, kFaceNodes * kFaceNodes> g{};  ///< g_ab, row-major over the active nodes
  };

  /// alpha: the dimensionless factor (gamma = alpha E). `boxes`: a distributed run's
  /// partition of the grid (Model::rank_boxes), `pts` being this rank's points (at the
  /// start of a load step, every point in its cells): the rank keeps the faces whose
  /// lowest node it owns (each face in one rank's share, its nodes near the rank's rows),
  /// those between a cell of its box and the next cell up in x, y or z, and learns the
  /// occupancy of such a next cell in another rank's box from that rank (neighbour
  /// messages, not a max over every cell of the grid on every rank).
  GhostFaces(const Grid<dim>& grid, const MaterialPoints<dim>& pts,
             const std::vector<std::shared_ptr<const Material>>& materials, const DofMap& dofs, double alpha,
             const RankBoxes& boxes = {}, bool axisymmetric = false)
      : axisymmetric_(axisymmetric) {
    const bool over_ranks = !boxes.empty();
    // The cells this rank looks at: its box and the next layer beyond its upper sides
    // (the whole grid serially), numbered within that window, so that no array is as
    // long as the grid on a distributed run's rank.
    const Window w(grid, over_ranks ? &boxes : nullptr);
    if (w.count == 0) return;  // (an empty box: no cells, no faces)
    // Points per cell and the stiffest material in each cell.
    std::vector<int> points_in(w.count, 0);
    std::vector<double> young(w.count, 0.0);
    const double young_max = stiffest_young(materials);
    for (int p = 0; p < pts.size(); ++p)
      if (const auto c = grid.cell_of(pts.position[p]); c && w.contains(*c)) {  // (a rank's: in its box)
        const int k = w.local(*c);
        ++points_in[k];
        young[k] = std::max(young[k], materials[pts.material[p]]->elasticity().young);
      }
    if (over_ranks) share_occupancy(grid, boxes, w, points_in, young);
    // Active cells (every node with dofs) and boundary cells (active; empty or beside an empty cell).
    std::vector<char> active(w.count, 0), boundary(w.count, 0);
    for (int k = 0; k < w.count; ++k) {
      const Index c = w.cell(k);
      active[k] = 1;
      for (int corner = 0; corner < (1 << dim); ++corner) {
        Index node = c;
        for (int d = 0; d < dim; ++d) node[d] += (corner >> d) & 1;
        if (!dofs.active(grid.node_index(node))) active[k] = 0;
      }
      boundary[k] = active[k] && points_in[k] == 0;
    }
    // The faces x_d = const between cells L (below) and R (above), in the grid's cell order.
    const auto& n = grid.cells();
    const Vec<dim>& h = grid.cell_size();
    for (int k = 0; k < w.count; ++k) {
      const Index left = w.cell(k);
      // A face's lowest node is its lower cell's key (every corner active): its owner's.
      if (over_ranks && boxes.owner(grid.node_index(left)) != ranks::rank()) continue;
      for (int d = 0; d < dim; ++d) {
        if (left[d] + 1 >= n[d]) continue;
        Index right = left;
        ++right[d];
        const int r = w.local(right);  // (in the window: one layer beyond the box)
        if (!active[k] || !active[r] || !(boundary[k] || boundary[r])) continue;
        double E = std::max(young[k], young[r]);
        if (E == 0.0) E = young_max;
        add_face(grid, dofs, left, d, alpha * E, h);
      }
    }
  }

  const std::vector<Face>& faces() const { return faces_; }

  int size() const { return static_cast<int>(faces_.size()); }

  /// f += G du (each displacement component independently).
  void add_force(const DofMap& dofs, const Vector& du, Vector& f) const {
    for (const Face& F : faces_)
      for (int a = 0; a < F.count; ++a)
        for (int i = 0; i < dim; ++i) {
          double v = 0.0;
          for (int b = 0; b < F.count; ++b) v += F.g[a * F.count + b] * du[dofs.dof(F.node[b], i)];
          f[dofs.dof(F.node[a], i)] += v;
        }
  }

  /// K += G; K's pattern must hold every face's nodes (pattern_groups()).
  void add_matrix(const DofMap& dofs, SparseMatrix& K) const {
    double* values = K.valuePtr();
    for (const Face& F : faces_)
      for (int b = 0; b < F.count; ++b)
        for (int i = 0; i < dim; ++i) {
          const int col = dofs.dof(F.node[b], i);
          for (int a = 0; a < F.count; ++a)
            values[pattern_offset(K, dofs.dof(F.node[a], i), col)] += F.g[a * F.count + b];
        }
  }

 private:
  using Index = typename Grid<dim>::Index;
  /// A box of cells [lo, lo + size) numbered within it (x fastest, as the grid's): a
  /// rank's box and the layer beyond its upper sides, clamped to the grid.
  struct Window {
    Index lo{}, size{};
    int count = 0;
    Window(const Grid<dim>& grid, const RankBoxes* boxes) {
      const auto& n = grid.cells();
      count = 1;
      const RankBoxes::Box box = boxes ? boxes->box(ranks::rank()) : RankBoxes::Box{};
      for (int d = 0; d < dim; ++d) {
        lo[d] = boxes ? box.lo[d] : 0;
        const int hi = boxes ? std::min(box.hi[d] + 1, n[d]) : n[d];  // exclusive
        size[d] = boxes && box.empty() ? 0 : hi - lo[d];
        count *= size[d];
      }
    }
    bool contains(const Index& c) const {
      for (int d = 0; d < dim; ++d)
        if (c[d] < lo[d] || c[d] >= lo[d] + size[d]) return false;
      return true;
    }
    int local(const Index& c) const {
      int k = 0;
      for (int d = dim - 1; d >= 0; --d) k = k * size[d] + (c[d] - lo[d]);
      return k;
    }
    Index cell(int k) const {
      Index c{};
      for (int d = 0; d < dim; ++d) {
        c[d] = lo[d] + k % size[d];
        k /= size[d];
      }
      return c;
    }
  };
  /// The occupancy (points, stiffest Young's modulus) of the cells next to this rank's
  /// box across its upper sides, from their owners: each rank sends the cells of its box's
  /// lower sides to the owner of the cell below them in that direction.
  static void share_occupancy(const Grid<dim>& grid, const RankBoxes& boxes, const Window& w,
                              std::vector<int>& points_in, std::vector<double>& young) {
    struct Cell {
      int number, points;  ///< the grid's cell number
      double young;
    };
    const auto& n = grid.cells();
    const int me = ranks::rank();
    const RankBoxes::Box box = boxes.box(me);
    std::vector<std::vector<Cell>> to(ranks::size());
    boxes.for_each_cell(me, [&](int key) {
      const Index c = grid.node_ijk(key);
      const int k = w.local(c);
      for (int d = 0; d < dim; ++d) {
        if (c[d] != box.lo[d] || c[d] == 0) continue;
        Index below = c;
        --below[d];
        const int r = boxes.owner(grid.node_index(below));
        const int number = cell_number(n, c);
        if (to[r].empty() || to[r].back().number != number) to[r].push_back({number, points_in[k], young[k]});
      }
    });
    for (const Cell& cell : ranks::send_to(to).received) {
      const Index c = cell_index(n, cell.number);
      if (!w.contains(c)) throw std::logic_error("GhostFaces: a cell's occupancy sent to a rank not beside it");
      points_in[w.local(c)] = cell.points;
      young[w.local(c)] = cell.young;
    }
  }

  static int cell_number(const Index& n, const Index& c) {
    int k = 0;
    for (int d = dim - 1; d >= 0; --d) k = k * n[d] + c[d];
    return k;
  }
  static Index cell_index(const Index& n, int k) {
    Index c{};
    for (int d = 0; d < dim; ++d) {
      c[d] = k % n[d];
      k /= n[d];
    }
    return c;
  }

  /// The face between cell `left` and its neighbour in direction d: the nodes of both
  /// cells (node planes k-1, k, k+1 in d), their jump coefficients and face integrals.
  void add_face(const Grid<dim>& grid, const DofMap& dofs, const Index& left, int d, double gamma, const Vec<dim>& h) {
    static constexpr double c[3] = {1.0, -2.0, 1.0};
    std::array<std::array<int, dim>, kFaceNodes> offset{};  // plane in d (0..2); 0/1 in the others
    std::array<int, kFaceNodes> node{};
    Face F;
    F.normal = d;
    for (int a = 0; a < kFaceNodes; ++a) {
      int code = a;
      Index ijk = left;
      for (int e = 0; e < dim; ++e) {
        offset[a][e] = e == d ? code % 3 : code % 2;
        code /= e == d ? 3 : 2;
        ijk[e] += offset[a][e];
      }
      node[a] = grid.node_index(ijk);
    }
    std::array<int, kFaceNodes> kept{};
    for (int a = 0; a < kFaceNodes; ++a)
      if (dofs.active(node[a])) {
        kept[F.count] = a;
        F.node[F.count++] = node[a];
      }
    if (F.count == 0) return;
    // (axisymmetric: a face r = r_F <= 0 has no extent per radian)
    const double face_radius = grid.origin()[0] + (left[0] + 1) * h[0];
    if (axisymmetric_ && d == 0 && face_radius <= 0.0) return;
    for (int i = 0; i < F.count; ++i)
      for (int j = 0; j < F.count; ++j) {
        const auto& oa = offset[kept[i]];
        const auto& ob = offset[kept[j]];
        double v = gamma / h[d] * c[oa[d]] * c[ob[d]];
        for (int e = 0; e < dim; ++e)
          if (e != d) v *= tangential_integral(grid, left, e, oa[e], ob[e]);
        if (axisymmetric_ && d == 0) v *= face_radius;
        F.g[i * F.count + j] = v;
      }
    faces_.push_back(F);
  }

  /// The integral, along the face's tangential direction e over cell `left`'s extent, of
  /// the hat functions of its node offsets a and b (0 or 1): h (1/3 or 1/6); per radian in
  /// r (axisymmetric, e = 0), of T_a T_b r over the part at r > 0.
  double tangential_integral(const Grid<dim>& grid, const Index& left, int e, int a, int b) const {
    const double h = grid.cell_size()[e];
    if (!axisymmetric_ || e != 0) return h * (a == b ? 1.0 / 3.0 : 1.0 / 6.0);
    const double r0 = grid.origin()[0] + left[0] * h, r1 = r0 + h;
    const double lo = std::max(r0, 0.0);
    if (lo >= r1) return 0.0;
    const double mid = 0.5 * (lo + r1), half = 0.5 * (r1 - lo), g = half / std::sqrt(3.0);
    double sum = 0.0;
    for (const double r : {mid - g, mid + g}) {
      const double t = (r - r0) / h;  // node offset 1's hat; offset 0's is 1 - t
      sum += (a ? t : 1.0 - t) * (b ? t : 1.0 - t) * r;
    }
    return half * sum;
  }

  bool axisymmetric_ = false;
  std::vector<Face> faces_;
};

}  // namespace gradmpm
