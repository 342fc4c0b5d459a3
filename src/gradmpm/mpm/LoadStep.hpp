#pragma once
// One load step of the implicit MPM on the grid (mpm/QuasiStatic.hpp runs the steps):
// stencils at x_n, active dofs, the sparsity pattern, the prescribed increments, and the
// point loop of every Newton iteration (internal force, tangent), then eq. (2): the
// converged increment mapped to the points. Internal to the driver.
#include <fmt/format.h>

#include <array>
#include <map>
#include <memory>
#include <string>

#include "gradmpm/core/Parallel.hpp"
#include "gradmpm/mpm/Model.hpp"
#include "gradmpm/points/Transfer.hpp"
#include "gradmpm/solver/Assembler.hpp"

namespace gradmpm::detail {

/// A Newton failure inside one load step (the caller cuts the increment).
struct StepFailure {
  std::string reason;
};

/// grad_n du = sum_a du_a (x) dN_a at one point (embedded in 3x3), and optionally the
/// point's displacement sum_a N_a du_a (eq. 2).
template <int dim>
Mat3 increment_gradient(const Stencil<dim>& s, const DofMap& dofs, const Vector& du, Vec<dim>* dx = nullptr) {
  Mat3 g = Mat3::Zero();
  if (dx) dx->setZero();
  for (int a = 0; a < s.count; ++a)
    for (int i = 0; i < dim; ++i) {
      const double u = du[dofs.dof(s.node[a], i)];
      if (dx) (*dx)[i] += s.N[a] * u;
      for (int j = 0; j < dim; ++j) g(i, j) += u * s.dN[a][j];
    }
  return g;
}

/// The grid-side work of one load step: stencils at x_n, active dofs, the sparsity
/// pattern, the prescribed increments, and the point loop of every Newton iteration.
template <int dim>
class LoadStep {
 public:
  LoadStep(const Model<dim>& m, double lambda_end, double dlambda)
      : model_(m),
        st_(evaluate_stencils(m.grid, m.points, m.basis)),
        dofs_(st_, m.grid.num_nodes(), dim),
        pattern_(build_pattern(st_, dofs_)),
        assembler_(st_, m.points, dofs_, &m.grid),
        response_(m.points.size()),
        trial_state_(m.points.state.size()) {
    // Prescribed increments of active constrained nodes (last definition wins).
    std::map<int, double> prescribed;
    for (const auto& c : m.constraints)
      if (dofs_.active(c.node)) prescribed[dofs_.dof(c.node, c.component)] = c.total * dlambda;
    for (const auto& [dof, value] : prescribed) {
      constrained_.push_back(dof);
      increments_.push_back(value);
    }
    // External force at the end of the step, eq. (1): f_i = sum_p N_i (m_p g + f_p) lambda.
    f_ext_ = Vector::Zero(dofs_.num_dofs());
    for (int p = 0; p < m.points.size(); ++p) {
      const Vec<dim> f = (m.points.mass[p] * m.gravity + m.points.force[p]) * lambda_end;
      const Stencil<dim>& s = st_[p];
      for (int a = 0; a < s.count; ++a)
        for (int i = 0; i < dim; ++i) f_ext_[dofs_.dof(s.node[a], i)] += s.N[a] * f[i];
    }
  }

  const DofMap& dofs() const { return dofs_; }
  const Vector& f_ext() const { return f_ext_; }
  const std::vector<int>& constrained() const { return constrained_; }
  const std::vector<double>& increments() const { return increments_; }
  const SparseMatrix& pattern() const { return pattern_; }
  bool symmetric_tangent() const { return model_.symmetric_tangent(); }

  /// Point loop for the iterate du: material updates (stress and history) and the
  /// internal force f_int,i = sum_p tau_p grad N_i w_p. The updates are independent and
  /// run on OpenMP threads; f_int is scattered by buckets of points with disjoint nodes
  /// (Assembler::for_each_point_disjoint), so the result does not depend on the threads.
  void internal_force(const Vector& du, Vector& f_int) {
    const auto& pts = model_.points;
    const int np = pts.size();
    f_int = Vector::Zero(dofs_.num_dofs());
    grads_.resize(np);
    weights_.resize(np);
    int inverted = -1;
    double inverted_det = 0.0;
#pragma omp parallel for schedule(static) if (use_threads(np))
    for (int p = 0; p < np; ++p) {
      const Stencil<dim>& s = st_[p];
      const Mat3 dF = Mat3::Identity() + increment_gradient(s, dofs_, du);
      const double detdF = dF.determinant();
      if (!(detdF > 0.0)) {
#pragma omp critical
        {
          inverted = p;
          inverted_det = detdF;
        }
        continue;
      }
      const Material& mat = model_.material_of(p);
      mat.update(dF, pts.state_of(p), trial_state_.data() + static_cast<std::size_t>(p) * pts.state_stride,
                 response_[p]);
      auto& G = grads_[p];  // gradients in the configuration the stress lives in
      if (mat.finite_strain()) {
        const Mat3 inv = dF.inverse();
        for (int a = 0; a < s.count; ++a)
          for (int l = 0; l < dim; ++l) {
            double v = 0.0;
            for (int m = 0; m < dim; ++m) v += s.dN[a][m] * inv(m, l);
            G[a][l] = v;
          }
        weights_[p] = pts.original_volume[p];  // Kirchhoff stress on V_p = sigma on v_p
      } else {
        for (int a = 0; a < s.count; ++a) G[a] = s.dN[a];
        weights_[p] = pts.volume[p];
      }
    }
    if (inverted >= 0) throw StepFailure{fmt::format("point {} inverted (det dF = {:.3g})", inverted, inverted_det)};
    assembler_.for_each_point_disjoint([&](int p) {
      const Stencil<dim>& s = st_[p];
      const auto& G = grads_[p];
      const Mat3& stress = response_[p].stress;
      for (int a = 0; a < s.count; ++a)
        for (int i = 0; i < dim; ++i) {
          double f = 0.0;
          for (int j = 0; j < dim; ++j) f += stress(i, j) * G[a][j];
          f_int[dofs_.dof(s.node[a], i)] += weights_[p] * f;
        }
    });
  }

  /// The tangent K at the state of the last internal_force(): each point's material
  /// tangent is formed inside the (coloured, threaded) scatter-add and never stored.
  void stiffness(SparseMatrix& K) const {
    K = pattern_;
    assembler_.add_matrix(K, [&](int p, const Stencil<dim>& s, typename Assembler<dim>::LocalMatrix& Ke) {
      // K_(a i)(b k) = w sum_j G_aj (sum_l A_ijkl G_bl): the inner sum once per node b.
      const auto& G = grads_[p];
      Mat9 A;
      model_.materials[model_.points.material[p]]->tangent(response_[p], dim, A);
      const double w = weights_[p];
      for (int b = 0; b < s.count; ++b) {
        double H[dim][dim][dim];  // H[i][j][k] = sum_l A_ijkl G_bl
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j)
            for (int k = 0; k < dim; ++k) {
              double v = 0.0;
              for (int l = 0; l < dim; ++l) v += A(3 * i + j, 3 * k + l) * G[b][l];
              H[i][j][k] = w * v;
            }
        for (int a = 0; a < s.count; ++a)
          for (int i = 0; i < dim; ++i)
            for (int k = 0; k < dim; ++k) {
              double v = 0.0;
              for (int j = 0; j < dim; ++j) v += G[a][j] * H[i][j][k];
              Ke(a * dim + i, b * dim + k) = v;
            }
      }
    });
  }

  /// Eq. (2): maps the converged increment to the points and updates their state.
  void commit(Model<dim>& m, const Vector& du) const {
    auto& pts = m.points;
    pts.state = trial_state_;  // the material histories of the converged iterate
    for (int p = 0; p < pts.size(); ++p) {
      Vec<dim> dx;
      const Mat3 g = increment_gradient(st_[p], dofs_, du, &dx);
      pts.position[p] += dx;
      pts.F[p] = (Mat3::Identity() + g) * pts.F[p];
      const double J = pts.F[p].determinant();
      pts.volume[p] = J * pts.original_volume[p];
      const MaterialResponse& r = response_[p];
      pts.stress[p] = m.material_of(p).finite_strain() ? Mat3(r.stress / J) : r.stress;
      if (m.basis == BasisKind::CPGIMP)
        for (int d = 0; d < dim; ++d) pts.half_length[p][d] = pts.original_half_length[p][d] * pts.F[p].col(d).norm();
    }
  }

  /// The active nodes' coordinates, one row per node in equation order.
  Eigen::MatrixXd node_coordinates() const {
    Eigen::MatrixXd x(dofs_.num_active_nodes(), dim);
    for (int e = 0; e < dofs_.num_active_nodes(); ++e)
      x.row(e) = model_.grid.node_position(dofs_.node_of(e)).transpose();
    return x;
  }

  /// After commit: frees what only Newton needed (pattern, responses, trial state,
  /// gradients), keeping the stencils and the equation numbering for the grid fields.
  void release_newton_data() {
    pattern_ = SparseMatrix();
    std::vector<MaterialResponse>().swap(response_);
    std::vector<double>().swap(trial_state_);
    std::vector<std::array<Vec<dim>, Stencil<dim>::capacity>>().swap(grads_);
    std::vector<double>().swap(weights_);
  }

  void keep_converged_force(const Vector& f_int) { f_int_converged_ = f_int; }

  /// A vector in equation numbering at every grid node (dim values per node; zero on
  /// inactive nodes): the increment du, or the reactions f_int - f_ext.
  Vector on_grid(const Vector& v) const {
    const int nn = model_.grid.num_nodes();
    Vector u = Vector::Zero(static_cast<Eigen::Index>(nn) * dim);
    for (int i = 0; i < dim; ++i) {
      const Vector gi = dofs_.to_grid(v, i);
      for (int n = 0; n < nn; ++n) u[n * dim + i] = gi[n];
    }
    return u;
  }
  Vector grid_reaction() const { return on_grid(f_int_converged_ - f_ext_); }

  /// Nodal mass sum_p N_i m_p at every grid node.
  Vector grid_mass() const {
    Vector mass = Vector::Zero(model_.grid.num_nodes());
    for (int p = 0; p < model_.points.size(); ++p)
      for (int a = 0; a < st_[p].count; ++a) mass[st_[p].node[a]] += st_[p].N[a] * model_.points.mass[p];
    return mass;
  }

 private:
  const Model<dim>& model_;
  PointStencils<dim> st_;
  DofMap dofs_;
  SparseMatrix pattern_;
  Assembler<dim> assembler_;
  std::vector<int> constrained_;
  std::vector<double> increments_;
  Vector f_ext_;
  std::vector<MaterialResponse> response_;
  std::vector<double> trial_state_;  ///< the state block of the current iterate
  Vector f_int_converged_;           ///< f_int at the converged iterate (reactions)
  std::vector<std::array<Vec<dim>, Stencil<dim>::capacity>> grads_;
  std::vector<double> weights_;
};

}  // namespace gradmpm::detail
