#pragma once
// Global operators as sums of material-point contributions (eq. 1 of the paper and
// its matrix analogue). The same point quadrature integrates the stiffness, the
// mass matrix M and the Laplacian L of the gradient step, and right-hand sides.
#include <Eigen/Dense>

#include "gradmpm/solver/SparsePattern.hpp"

namespace gradmpm {

template <int dim>
class Assembler {
 public:
  static constexpr int max_local = Stencil<dim>::capacity * dim;
  /// Local matrix of one point: (count*ncomp)^2, stack storage only.
  using LocalMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor,
                                    max_local, max_local>;

  Assembler(const PointStencils<dim>& stencils, const MaterialPoints<dim>& points,
            const DofMap& dofs)
      : st_(stencils), points_(points), dofs_(dofs) {}

  const DofMap& dofs() const { return dofs_; }

  /// A += sum_p K_p, where kernel(p, stencil, K_p) fills the local matrix of point p
  /// (local index a*ncomp + comp). A must hold the pattern of build_pattern().
  template <class Kernel>
  void add_matrix(SparseMatrix& A, Kernel&& kernel) const {
    // Points run on OpenMP threads, each with its own local matrix; the scatter-add into
    // the shared values uses atomic adds (the result equals the serial one up to the
    // order of floating-point additions).
    const int nc = dofs_.ncomp();
    double* values = A.valuePtr();
    const int np = points_.size();
#pragma omp parallel
    {
      LocalMatrix Ke;
#pragma omp for schedule(static)
      for (int p = 0; p < np; ++p) {
        const Stencil<dim>& s = st_[p];
        Ke.setZero(s.count * nc, s.count * nc);
        kernel(p, s, Ke);
        for (int b = 0; b < s.count; ++b)
          for (int cb = 0; cb < nc; ++cb) {
            const int col = dofs_.dof(s.node[b], cb);
            for (int a = 0; a < s.count; ++a) {
              // The components of a node are consecutive rows of every column: one
              // search per node, not per component.
              const int k0 = pattern_offset(A, dofs_.dof(s.node[a], 0), col);
              for (int ca = 0; ca < nc; ++ca) {
#pragma omp atomic
                values[k0 + ca] += Ke(a * nc + ca, b * nc + cb);
              }
            }
          }
      }
    }
  }

  /// M_ij = sum_p N_i(x_p) N_j(x_p) V_p   (one component per node)
  void add_mass(SparseMatrix& A, double scale = 1.0) const {
    add_matrix(A, [&](int p, const Stencil<dim>& s, LocalMatrix& K) {
      const double w = scale * points_.volume[p];
      for (int a = 0; a < s.count; ++a)
        for (int b = 0; b < s.count; ++b) K(a, b) = w * s.N[a] * s.N[b];
    });
  }

  /// L_ij = sum_p grad N_i(x_p) . grad N_j(x_p) V_p   (the weak form of -laplacian)
  void add_laplacian(SparseMatrix& A, double scale = 1.0) const {
    add_matrix(A, [&](int p, const Stencil<dim>& s, LocalMatrix& K) {
      const double w = scale * points_.volume[p];
      for (int a = 0; a < s.count; ++a)
        for (int b = 0; b < s.count; ++b) K(a, b) = w * s.dN[a].dot(s.dN[b]);
    });
  }

  /// (M + l2 L)_ij in one pass over the points: the Helmholtz operator of the gradient step.
  void add_helmholtz(SparseMatrix& A, double l2) const {
    add_matrix(A, [&](int p, const Stencil<dim>& s, LocalMatrix& K) {
      const double w = points_.volume[p];
      for (int a = 0; a < s.count; ++a)
        for (int b = 0; b < s.count; ++b) K(a, b) = w * (s.N[a] * s.N[b] + l2 * s.dN[a].dot(s.dN[b]));
    });
  }

  /// q_p = sum_i N_i(x_p) q_i: a scalar nodal field (equation numbering) at the points (eq. 2).
  std::vector<double> interpolate(const Vector& nodal) const {
    std::vector<double> q(points_.size());
    for (int p = 0; p < points_.size(); ++p) {
      const Stencil<dim>& s = st_[p];
      double v = 0.0;
      for (int a = 0; a < s.count; ++a) v += s.N[a] * nodal[dofs_.dof(s.node[a], 0)];
      q[p] = v;
    }
    return q;
  }

  /// f_i = sum_p N_i(x_p) q_p V_p   (eq. 1 with a point "force" q_p V_p)
  Vector load(const std::vector<double>& q) const {
    Vector f = Vector::Zero(dofs_.num_dofs());
    for (int p = 0; p < points_.size(); ++p) {
      const Stencil<dim>& s = st_[p];
      for (int a = 0; a < s.count; ++a)
        f[dofs_.dof(s.node[a], 0)] += s.N[a] * q[p] * points_.volume[p];
    }
    return f;
  }

  /// f_i = sum_p dN_i/dx_d(x_p) q_p V_p   (the weak divergence of a point field)
  Vector gradient_load(const std::vector<double>& q, int d) const {
    Vector f = Vector::Zero(dofs_.num_dofs());
    for (int p = 0; p < points_.size(); ++p) {
      const Stencil<dim>& s = st_[p];
      for (int a = 0; a < s.count; ++a)
        f[dofs_.dof(s.node[a], 0)] += s.dN[a][d] * q[p] * points_.volume[p];
    }
    return f;
  }

 private:
  const PointStencils<dim>& st_;
  const MaterialPoints<dim>& points_;
  const DofMap& dofs_;
};

}  // namespace gradmpm
