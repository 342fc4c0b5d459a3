#pragma once
// Global operators as sums of material-point contributions (eq. 1 of the paper and
// its matrix analogue). The same point quadrature integrates the stiffness, the
// mass matrix M and the Laplacian L of the gradient step, and right-hand sides.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <limits>

#include "gradmpm/core/Parallel.hpp"
#include "gradmpm/solver/SparsePattern.hpp"

namespace gradmpm {

/// `max_comp`: the most components per node of the systems it assembles (dim for the
/// displacements; dim + 1 with the pore pressure, mpm/Consolidation.hpp).
template <int dim, int max_comp = dim>
class Assembler {
 public:
  static constexpr int max_local = Stencil<dim>::capacity * max_comp;
  /// add_matrix(): node blocks of a column searched forward before a binary search.
  static constexpr int kLookAhead = 4;
  /// Local matrix of one point: (count*ncomp)^2, stack storage only.
  using LocalMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, max_local, max_local>;

  /// With the grid, points are put in strips for race-free threaded assembly (below); without
  /// it the scatter-add is serial. (A distributed run's assembler is given its rank's
  /// points, mpm/RankPoints.hpp.)
  Assembler(const PointStencils<dim>& stencils, const MaterialPoints<dim>& points, const DofMap& dofs,
            const Grid<dim>* grid = nullptr)
      : st_(stencils), points_(points), dofs_(dofs), subset_(points.size()) {
    for (int p = 0; p < points.size(); ++p) subset_[p] = p;
    if (grid) build_strips(*grid);
  }

  const DofMap& dofs() const { return dofs_; }

  /// Calls f(p) for every point; concurrent calls (OpenMP threads) are given points whose
  /// stencils share no node, so f may add into nodal arrays without atomics. Points are
  /// grouped in buckets by the lowest node of their stencil (its anchor), and the buckets
  /// in strips of kStripWidth rows of anchors across the grid's outermost direction (the
  /// slowest-varying node index). A stencil spans at most 3 nodes per direction, so a
  /// strip's stencils reach at most kStripWidth + 2 node rows, and strips two apart touch
  /// disjoint nodes: the even strips run in parallel, then the odd ones; the buckets of a
  /// strip run in order of their anchors (memory order of the matrix's columns, so the
  /// scatter finds them in cache), the points of a bucket in order. The additions into
  /// each node happen in the same order whatever the thread count, so results are
  /// identical bit for bit.
  template <class F>
  void for_each_point_disjoint(F&& f) const {
    if (!in_strips_) {
      for (int p : subset_) f(p);
      return;
    }
    for_each_bucket([&](const int* first, const int* last) {
      for (const int* p = first; p != last; ++p) f(*p);
    });
  }

  /// Calls f(first, last) for each run [first, last) of consecutive points with the same
  /// stencil nodes, concurrently for runs of disjoint nodes as above.
  /// The runs of the strips are found once (build_strips: run_length_): finding them here
  /// compared the stencils of points in bucket order, which lie apart in memory, and the
  /// loads it waited for were most of the internal force's scatter (perf, 1e5 dof in 2D).
  template <class F>
  void for_each_run(F&& f) const {
    if (!in_strips_) {
      const int* p = subset_.data();
      const int* end = p + subset_.size();
      for (const int* q; p != end; p = q) {
        q = run_end(p, end);
        f(p, q);
      }
      return;
    }
    const int* order = order_.data();
    const int* length = run_length_.data();
    for_each_bucket([&](const int* first, const int* last) {
      for (const int* p = first; p != last; p += length[p - order]) f(p, p + length[p - order]);
    });
  }

  /// A += sum_p K_p, where kernel(p, stencil, Ke) adds the local matrix of point p into Ke
  /// (local index a*ncomp + comp). A must hold the pattern of build_pattern().
  /// Consecutive points of a bucket with the same stencil nodes (build_strips() sorts them so)
  /// share one Ke: their sum is scattered once. The scatter's searches of the pattern,
  /// not the local products, were most of the assembly (perf, column_2d at 1e5 dof), and
  /// with 2 points per cell and direction about 2^dim points share each stencil.
  /// `lower_only`: every K_p is symmetric and the kernel adds only its lower triangle
  /// (entries r >= c, or more); the sum of a run is mirrored before the scatter.
  template <class Kernel>
  void add_matrix(SparseMatrix& A, Kernel&& kernel, bool lower_only = false) const {
    const int nc = dofs_.ncomp();
    double* values = A.valuePtr();
    auto scatter = [&](const Stencil<dim>& s, const LocalMatrix& Ke) {
      const int* outer = A.outerIndexPtr();
      const int* inner = A.innerIndexPtr();
      std::array<int, Stencil<dim>::capacity> at;  // row of node a's first component in b's columns
      for (int b = 0; b < s.count; ++b) {
        // The nc columns of node b hold the same rows (build_pattern: node blocks), so the
        // rows are found once, in its first column. The rows of a stencil's next node are
        // usually a few node blocks further on (the next entry within a row of the grid, two
        // on to the next row in 2D): looked for there first, by kLookAhead steps of a node
        // block; otherwise (the next plane in 3D) by binary search.
        const int col = dofs_.dof(s.node[b], 0);
        const int begin = outer[col], len = outer[col + 1] - begin;
        int k = -1, prev = -1;
        for (int a = 0; a < s.count; ++a) {
          const int row = dofs_.dof(s.node[a], 0);
          int found = -1;
          if (k >= 0 && row > prev)
            for (int j = k + nc, steps = 0; j < len && steps < kLookAhead && inner[begin + j] <= row; j += nc, ++steps)
              if (inner[begin + j] == row) {
                found = j;
                break;
              }
          k = found >= 0 ? found : pattern_offset(A, row, col) - begin;
          at[a] = k;
          prev = row;
        }
        for (int cb = 0; cb < nc; ++cb) {
          double* column = values + begin + cb * len;
          for (int a = 0; a < s.count; ++a)
            for (int ca = 0; ca < nc; ++ca) column[at[a] + ca] += Ke(a * nc + ca, b * nc + cb);
        }
      }
    };
    for_each_run([&](const int* first, const int* last) {
      LocalMatrix Ke;  // fixed capacity: on the stack
      const Stencil<dim>& s = st_[*first];
      Ke.setZero(s.count * nc, s.count * nc);
      for (const int* p = first; p != last; ++p) kernel(*p, st_[*p], Ke);
      if (lower_only) Ke.template triangularView<Eigen::StrictlyUpper>() = Ke.transpose();
      scatter(s, Ke);
    });
  }

  /// M_ij = sum_p N_i(x_p) N_j(x_p) V_p   (one component per node)
  void add_mass(SparseMatrix& A, double scale = 1.0) const {
    add_matrix(A, [&](int p, const Stencil<dim>& s, LocalMatrix& K) {
      const double w = scale * points_.volume[p];
      for (int a = 0; a < s.count; ++a)
        for (int b = 0; b < s.count; ++b) K(a, b) += w * s.N[a] * s.N[b];
    });
  }

  /// L_ij = sum_p grad N_i(x_p) . grad N_j(x_p) V_p   (the weak form of -laplacian)
  void add_laplacian(SparseMatrix& A, double scale = 1.0) const {
    add_matrix(A, [&](int p, const Stencil<dim>& s, LocalMatrix& K) {
      const double w = scale * points_.volume[p];
      for (int a = 0; a < s.count; ++a)
        for (int b = 0; b < s.count; ++b) K(a, b) += w * s.dN[a].dot(s.dN[b]);
    });
  }

  /// (M + l2 L)_ij in one pass over the points: the Helmholtz operator of the gradient step.
  void add_helmholtz(SparseMatrix& A, double l2) const {
    add_matrix(A, [&](int p, const Stencil<dim>& s, LocalMatrix& K) {
      const double w = points_.volume[p];
      for (int a = 0; a < s.count; ++a)
        for (int b = 0; b < s.count; ++b) K(a, b) += w * (s.N[a] * s.N[b] + l2 * s.dN[a].dot(s.dN[b]));
    });
  }

  /// q_p = sum_i N_i(x_p) q_i: a scalar nodal field (equation numbering) at the points (eq. 2).
  std::vector<double> interpolate(const Vector& nodal) const {
    std::vector<double> q(points_.size());
    interpolate_columns(nodal, [&](int p, int, double v) { q[p] = v; });
    return q;
  }

  /// f_i = sum_p N_i(x_p) q_p V_p   (eq. 1 with a point "force" q_p V_p)
  Vector load(const std::vector<double>& q) const {
    Vector f = Vector::Zero(dofs_.num_dofs());
    for (const int p : subset_) {
      const Stencil<dim>& s = st_[p];
      for (int a = 0; a < s.count; ++a) f[dofs_.dof(s.node[a], 0)] += s.N[a] * q[p] * points_.volume[p];
    }
    return f;
  }

  /// Several point fields at once: F(i, j) = sum_p N_i(x_p) q_p[j] V_p, scattered by
  /// disjoint buckets (threads, no atomics). `q(p, j)` returns component j at point p.
  template <class Q>
  Eigen::MatrixXd load_columns(int ncols, Q&& q) const {
    Eigen::MatrixXd F = Eigen::MatrixXd::Zero(dofs_.num_dofs(), ncols);
    for_each_point_disjoint([&](int p) {
      const Stencil<dim>& s = st_[p];
      for (int a = 0; a < s.count; ++a) {
        const int i = dofs_.dof(s.node[a], 0);
        const double w = s.N[a] * points_.volume[p];
        for (int j = 0; j < ncols; ++j) F(i, j) += w * q(p, j);
      }
    });
    return F;
  }

  /// The nodal fields G (one per column, equation numbering) at every point:
  /// out(p, j, value) receives sum_i N_i(x_p) G(i, j). Threads over points.
  template <class Derived, class Out>
  void interpolate_columns(const Eigen::MatrixBase<Derived>& G, Out&& out) const {
    const int np = points_.size(), ncols = static_cast<int>(G.cols());
#pragma omp parallel for schedule(static) if (use_threads(np))
    for (int p = 0; p < np; ++p) {
      const Stencil<dim>& s = st_[p];
      for (int j = 0; j < ncols; ++j) {
        double v = 0.0;
        for (int a = 0; a < s.count; ++a) v += s.N[a] * G(dofs_.dof(s.node[a], 0), j);
        out(p, j, v);
      }
    }
  }

  /// f_i = sum_p dN_i/dx_d(x_p) q_p V_p   (the weak divergence of a point field)
  Vector gradient_load(const std::vector<double>& q, int d) const {
    Vector f = Vector::Zero(dofs_.num_dofs());
    for (int p = 0; p < points_.size(); ++p) {
      const Stencil<dim>& s = st_[p];
      for (int a = 0; a < s.count; ++a) f[dofs_.dof(s.node[a], 0)] += s.dN[a][d] * q[p] * points_.volume[p];
    }
    return f;
  }

 private:
  /// Anchor rows per strip (for_each_point_disjoint). Two is the least that keeps strips of
  /// one parity apart; a fixed number, not one chosen by the thread count, so that the
  /// order of the additions, and with it the results, do not depend on the threads.
  static constexpr int kStripWidth = 2;

  /// Buckets and strips as flat arrays: the points of bucket b are
  /// order_[bucket_start_[b] .. bucket_start_[b + 1]), the buckets of strip s are
  /// strip_start_[s] .. strip_start_[s + 1]), the strips of parity q are listed in
  /// strips_of_parity_[q] (one allocation each, not one per bucket). Empty strips and
  /// buckets are not stored.
  void build_strips(const Grid<dim>& grid) {
    const int np = static_cast<int>(subset_.size()), nn = grid.num_nodes();
    std::vector<int> anchor_of(np);  // of subset_[k], by k
#pragma omp parallel for schedule(static) if (use_threads(np))
    for (int k = 0; k < np; ++k) {
      const Stencil<dim>& s = st_[subset_[k]];
      typename Grid<dim>::Index anchor;
      anchor.fill(std::numeric_limits<int>::max());
      for (int a = 0; a < s.count; ++a) {
        const auto ijk = grid.node_ijk(s.node[a]);
        for (int d = 0; d < dim; ++d) anchor[d] = std::min(anchor[d], ijk[d]);
      }
      anchor_of[k] = grid.node_index(anchor);
    }
    // Points by anchor (a counting sort: buckets in node order, points in index order).
    std::vector<int> first(nn + 1, 0);
    for (int k = 0; k < np; ++k) ++first[anchor_of[k] + 1];
    for (int n = 0; n < nn; ++n) first[n + 1] += first[n];
    order_.resize(np);
    {
      std::vector<int> next(first.begin(), first.end() - 1);
      for (int k = 0; k < np; ++k) order_[next[anchor_of[k]]++] = subset_[k];
    }
    // Non-empty buckets, and the strips they fall in (node order is strip order).
    bucket_start_.clear();
    strip_start_.clear();
    for (auto& list : strips_of_parity_) list.clear();
    int last_strip = -1;
    for (int n = 0; n < nn; ++n) {
      if (first[n] == first[n + 1]) continue;
      const int strip = grid.node_ijk(n)[dim - 1] / kStripWidth;
      if (strip != last_strip) {
        strips_of_parity_[strip % 2].push_back(static_cast<int>(strip_start_.size()));
        strip_start_.push_back(static_cast<int>(bucket_start_.size()));
        last_strip = strip;
      }
      bucket_start_.push_back(first[n]);
    }
    bucket_start_.push_back(np);
    strip_start_.push_back(static_cast<int>(bucket_start_.size()) - 1);
    // Within a bucket, the points of one stencil together (for_each_run), in index order.
    auto before = [&](int p, int q) {
      const Stencil<dim>&s = st_[p], &t = st_[q];
      return std::lexicographical_compare(s.node.begin(), s.node.begin() + s.count, t.node.begin(),
                                          t.node.begin() + t.count);
    };
    const int nb = static_cast<int>(bucket_start_.size()) - 1;
    run_length_.assign(np, 0);
#pragma omp parallel for schedule(static) if (use_threads(np))
    for (int b = 0; b < nb; ++b) {
      std::stable_sort(order_.begin() + bucket_start_[b], order_.begin() + bucket_start_[b + 1], before);
      const int* order = order_.data();
      const int* last = order + bucket_start_[b + 1];
      for (const int* p = order + bucket_start_[b]; p != last;) {  // the bucket's runs (for_each_run)
        const int* q = run_end(p, last);
        run_length_[p - order] = static_cast<int>(q - p);
        p = q;
      }
    }
    in_strips_ = true;
  }

  /// The end of the run of points in [first, last) with the stencil nodes of *first.
  const int* run_end(const int* first, const int* last) const {
    const int* q = first + 1;
    while (q != last && same_nodes(st_[*first], st_[*q])) ++q;
    return q;
  }

  static bool same_nodes(const Stencil<dim>& s, const Stencil<dim>& t) {
    if (s.count != t.count) return false;
    for (int a = 0; a < s.count; ++a)  // a loop, not std::equal: that was a memcmp call per pair
      if (s.node[a] != t.node[a]) return false;
    return true;
  }

  /// f(first, last) for the points of every bucket: the even strips on threads, then the
  /// odd ones; a strip's buckets in order on one thread.
  template <class F>
  void for_each_bucket(F&& f) const {
    for (const std::vector<int>& strips : strips_of_parity_) {
      const int count = static_cast<int>(strips.size());
#pragma omp parallel for schedule(dynamic, 1) if (use_threads(points_.size()))
      for (int k = 0; k < count; ++k)
        for (int b = strip_start_[strips[k]]; b < strip_start_[strips[k] + 1]; ++b)
          f(order_.data() + bucket_start_[b], order_.data() + bucket_start_[b + 1]);
    }
  }

  const PointStencils<dim>& st_;
  const MaterialPoints<dim>& points_;
  const DofMap& dofs_;
  std::vector<int> subset_;  ///< every point, in index order (an assembler without strips runs over it)
  bool in_strips_ = false;
  std::vector<int> strip_start_, bucket_start_, order_;  ///< build_strips(): strip -> buckets -> points
  /// build_strips(): at the position in order_ where a run of points with the same stencil
  /// nodes begins, its length (0 elsewhere); runs do not cross buckets
  std::vector<int> run_length_;
  std::array<std::vector<int>, 2> strips_of_parity_;     ///< build_strips(): the even strips, the odd strips
};

}  // namespace gradmpm
