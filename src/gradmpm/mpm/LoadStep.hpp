#pragma once
// One load step of the implicit MPM on the grid (mpm/QuasiStatic.hpp runs the steps):
// stencils at x_n, active dofs, the sparsity pattern, the prescribed increments, and the
// point loop of every Newton iteration (internal force, tangent), then eq. (2): the
// converged increment mapped to the points. Internal to the driver.
//
// In a distributed run the model holds this rank's points only (Model::point_ids,
// mpm/RankPoints.hpp) and the step works on them alone: their stencils, updates, internal forces,
// their share of the tangent and the map to them. What needs every rank's points is
// summed or gathered where it is made: the active nodes (so every rank numbers the same
// equations), the supports of F-bar's weak-node cut, the cells' occupancy of the ghost
// penalty, f_ext, f_int, the nodal masses, the rigid boxes' forces, and a point that
// fails (outside the grid, inverted).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

#include "gradmpm/core/DefaultInitAllocator.hpp"
#include "gradmpm/core/Parallel.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/mpm/FBar.hpp"
#include "gradmpm/mpm/GhostPenalty.hpp"
#include "gradmpm/mpm/IncrementGradient.hpp"
#include "gradmpm/mpm/Model.hpp"
#include "gradmpm/mpm/PointPartition.hpp"
#include "gradmpm/mpm/RigidContact.hpp"
#include "gradmpm/points/Transfer.hpp"
#include "gradmpm/solver/Assembler.hpp"
#include "gradmpm/solver/RowHalo.hpp"
#include "gradmpm/solver/nonlinear/NonlinearProblem.hpp"

namespace gradmpm::detail {

/// The grid-side work of one load step: stencils at x_n, active dofs, the sparsity
/// pattern, the prescribed increments, and the point loop of every Newton iteration. The
/// quasi-static problem Newton solves (R = f_ext - f_int; solver/nonlinear/NonlinearProblem.hpp).
template <int dim>
class LoadStep final : public ParametrisedProblem {
 public:
  /// `m`: the model of the points the step works on; in a distributed run this rank's
  /// (Model::point_ids: their numbers in the whole body, by which messages name them).
  LoadStep(const Model<dim>& m, double lambda_end, double dlambda)
      : model_(m),
        split_(ranks::distributed()),
        ids_(split_ && m.point_ids.size() != static_cast<std::size_t>(m.points.size())
                 ? throw std::logic_error("a distributed run's load step needs the points owned (own_rank_points)")
                 : m.point_ids),
        st_(stencils(m, split_ ? &ids_ : nullptr)),
        fbar_(m.fbar ? std::make_unique<FBarCells<dim>>(m.grid, m.points, st_) : nullptr),
        dofs_(st_, m.grid.num_nodes(), dim, m.rank_boxes, ghost_margin),
        ghost_(m.ghost_penalty > 0.0
                   ? std::make_unique<GhostFaces<dim>>(m.grid, m.points, m.materials, dofs_, m.ghost_penalty,
                                                       m.rank_boxes, m.axisymmetric)
                   : nullptr),
        contact_(m.rigid_boxes.empty()
                     ? nullptr
                     : std::make_unique<RigidContact<dim>>(m.rigid_boxes, m.points, st_, dofs_, lambda_end, dlambda,
                                                         m.axisymmetric)),
        assembler_(st_, m.points, dofs_, &m.grid),
        response_(m.points.size()),
        trial_state_(m.points.state.size()) {
    // Prescribed increments of active constrained nodes (last definition wins).
    std::map<int, std::pair<double, double>> prescribed;  // (increment, total)
    for (const auto& c : m.constraints)
      if (dofs_.active(c.node)) prescribed[dofs_.dof(c.node, c.component)] = {c.total * dlambda, c.total};
    for (const auto& [dof, value] : prescribed) {
      constrained_.push_back(dof);
      increments_.push_back(value.first);
      totals_.push_back(value.second);
      largest_increment_ = std::max(largest_increment_, std::abs(value.first));
    }
    // (a distributed run's ranks know the constrained nodes of their own and ghost rows)
    if (split_) ranks::max(&largest_increment_, 1);
    for (const NodeTie& t : m.ties)  // (a tie to a node no point reaches holds nothing)
      if (dofs_.active(t.a) && dofs_.active(t.b)) active_ties_.push_back(t);
    if (split_ && !active_ties_.empty()) throw std::logic_error("[[ties]] run on one rank");
    if (fbar_) {
      all_cells_.resize(fbar_->members().size());
      for (std::size_t c = 0; c < all_cells_.size(); ++c) all_cells_[c] = static_cast<int>(c);
    }
    // After the constraints. Swapped in: Eigen 3.4's SparseMatrix has no move assignment,
    // and `tangent_ = make_pattern()` copied the pattern (36 MB at 1e5 dof in 2D, on new
    // pages where the step's pattern is larger than any before).
    SparseMatrix pattern = make_pattern();
    tangent_.swap(pattern);
    if (split_) halo_ = RowHalo(dofs_.rank_rows(), touched_rows(tangent_), dofs_.global_rows());
    // Eq. (1) at the step's end, scattered by strips on the threads (serially 8 ms per step
    // for 2e5 points in 2D).
    f_ext_ = Vector::Zero(dofs_.num_dofs());
    const double g_factor = m.dead_gravity ? 1.0 : lambda_end;
    assembler_.for_each_point_disjoint(
        [&](int p) { add_external_force(st_, m.points, m.gravity, g_factor, lambda_end, dofs_, p, f_ext_); });
    halo_.sum(f_ext_);  // every rank's points' share, in own and ghost rows
    if (m.dead_gravity) {  // the part that does not scale with lambda
      f_dead_ = Vector::Zero(dofs_.num_dofs());
      assembler_.for_each_point_disjoint(
          [&](int p) { add_external_force(st_, m.points, m.gravity, 1.0, 0.0, dofs_, p, f_dead_); });
      halo_.sum(f_dead_);
    }
    if (split_) {  // this rank's points' nodal masses, in the first component's rows (grid_fields; as nodal_mass)
      mass_ = Vector::Zero(dofs_.num_dofs());
      for (std::size_t p = 0; p < st_.size(); ++p)
        for (int a = 0; a < st_[p].count; ++a) mass_[dofs_.dof(st_[p].node[a], 0)] += st_[p].N[a] * m.points.mass[p];
    }
  }

  const DofMap& dofs() const override { return dofs_; }
  /// A distributed run's rows: this rank's and its ghosts' (those of its pattern's nodes
  /// in other ranks' rows); serially every row is this rank's.
  const RowHalo& halo() const override { return halo_; }
  /// The external force (a distributed run's: right in own and ghost rows).
  const Vector& f_ext() const { return f_ext_; }
  /// The part of f_ext that scales with the load factor (all of it but a dead gravity).
  Vector live_load() const { return f_dead_.size() ? Vector(f_ext_ - f_dead_) : f_ext_; }
  /// The internal force at the last residual()'s iterate.
  const Vector& f_int() const { return f_int_; }
  const std::vector<int>& constrained() const override { return constrained_; }
  const std::vector<double>& increments() const override { return increments_; }
  /// The largest prescribed increment (in size) over every rank's.
  double largest_increment() const override { return largest_increment_; }
  /// The tangent's pattern (its values: the last stiffness()'s).
  const SparseMatrix& pattern() const override { return tangent_; }

  /// r = f_ext - f_int at du, zero in the constrained rows; its norm against the larger of
  /// |f_ext| and |f_int| (every row: the reactions count), with one reduction over the ranks.
  ResidualNorms residual(const Vector& du, Vector& r) override {
    internal_force(du, f_int_);
    r = f_ext_ - f_int_;
    for (int c : constrained_) r[c] = 0.0;
    const auto [f_ext_norm, f_int_norm, r_norm] = halo_.norms<3>({&f_ext_, &f_int_, &r});
    // (std::max would drop a NaN: a failed material update must not read as balance)
    const bool finite = std::isfinite(f_ext_norm) && std::isfinite(f_int_norm);
    return {r_norm, finite ? std::max(f_ext_norm, f_int_norm) : std::numeric_limits<double>::quiet_NaN()};
  }
  SparseMatrix& tangent(bool share) override { return stiffness(share); }

  /// The arc-length method's load factor (ParametrisedProblem). The rigid boxes stay where
  /// the step was made for (a case with boxes is not run by arc-length).
  void set_load_factor(double lambda_end, double dlambda) override {
    f_ext_ = lambda_end * reference_load();
    if (f_dead_.size()) f_ext_ += f_dead_;
    largest_increment_ = 0.0;
    for (std::size_t k = 0; k < totals_.size(); ++k) {
      increments_[k] = dlambda * totals_[k];
      largest_increment_ = std::max(largest_increment_, std::abs(increments_[k]));
    }
    if (split_) ranks::max(&largest_increment_, 1);
  }
  /// Eq. (1) at load factor 1, less a dead gravity.
  const Vector& reference_load() override {
    if (f_ref_.size() == 0) {
      f_ref_ = Vector::Zero(dofs_.num_dofs());
      const double g_factor = model_.dead_gravity ? 0.0 : 1.0;
      assembler_.for_each_point_disjoint(
          [&](int p) { add_external_force(st_, model_.points, model_.gravity, g_factor, 1.0, dofs_, p, f_ref_); });
      halo_.sum(f_ref_);
    }
    return f_ref_;
  }
  const std::vector<double>& reference_increments() const override { return totals_; }
  Eigen::MatrixXd node_coordinates() const override { return dofs_.coordinates(model_.grid); }
  const PointStencils<dim>& stencils() const { return st_; }
  /// Point p's shape-function gradients at the last internal_force() iterate, in the
  /// configuration its stress lives in: grad_x N = dN dF^-1 (finite strain), dN at x_n
  /// (small strain).
  const std::array<Vec<dim>, Stencil<dim>::capacity>& gradients(int p) const { return grads_[p]; }
  /// Point p's weight w_p in f_int = sum_p w_p stress_p grad N at the last internal_force() iterate.
  double weight(int p) const { return weights_[p]; }
  /// F-bar's cells (null without F-bar).
  const FBarCells<dim>* fbar_cells() const { return fbar_.get(); }
  /// F-bar: each point's dJ and its cell's dJbar at the last internal_force() iterate.
  const std::vector<double>& fbar_dJ() const { return fbar_dJ_; }
  const std::vector<double>& fbar_dJbar() const { return fbar_dJbar_; }
  /// The increment point p's material sees: dF, or with F-bar (dJbar / dJ)^(1/dim) dF in
  /// the plane (dJbar and dJ of the last internal_force() iterate).
  Mat3 material_increment(int p, Mat3 dF) const {
    if (!fbar_) return dF;
    if (model_.axisymmetric) return dF * std::cbrt(fbar_dJbar_[p] / fbar_dJ_[p]);  // (the hoop stretch too)
    dF.template topLeftCorner<dim, dim>() *= std::pow(fbar_dJbar_[p] / fbar_dJ_[p], 1.0 / dim);
    return dF;
  }
  /// The state block of the last internal_force() iterate.
  const std::vector<double>& trial_state() const { return trial_state_; }
  /// The round-off of the internal force: 100 eps_mach E h^(dim-1) sqrt(dofs), the norm of
  /// nodal forces from a stress error of eps_mach E (what the strain of a step cannot
  /// resolve). Newton stops below it whatever the relative residual says (tiny strains).
  double roundoff_force() const override {
    const double young = stiffest_young(model_.materials);
    const double area = model_.grid.cell_size().prod() / model_.grid.cell_size().maxCoeff();
    return 100.0 * std::numeric_limits<double>::epsilon() * young * area * std::sqrt(double(dofs_.num_global_dofs()));
  }
  bool symmetric_tangent() const override { return model_.symmetric_tangent(); }

  /// Point loop for the iterate du: material updates (stress and history) and the
  /// internal force f_int,i = sum_p tau_p grad N_i w_p. The updates are independent and
  /// run on OpenMP threads; f_int is scattered by buckets of points with disjoint nodes
  /// (Assembler::for_each_point_disjoint), so the result does not depend on the threads.
  /// In a distributed run each rank updates its own points and f_int is summed in its
  /// own and ghost rows (RowHalo).
  void internal_force(const Vector& du, Vector& f_int) {
    if (fbar_) return internal_force_fbar(du, f_int);
    const auto& pts = model_.points;
    const int np = pts.size();
    f_int = Vector::Zero(dofs_.num_dofs());
    grads_.resize(np);
    weights_.resize(np);
    if (model_.axisymmetric) hoop_.resize(np);
    int inverted = kNone;
    double inverted_det = 0.0;
#pragma omp parallel for schedule(static) if (use_threads(np))
    for (int p = 0; p < np; ++p) {
      const Stencil<dim>& s = st_[p];
      const Mat3 g = point_increment(p, du);
      const Mat3 dF = Mat3::Identity() + g;
      const double detdF = dF.determinant();
      if (!(detdF > 0.0)) {
#pragma omp critical
        if (id(p) < inverted) {
          inverted = id(p);
          inverted_det = detdF;
        }
        continue;
      }
      const Material& mat = model_.material_of(p);
      mat.update_increment(g, pts.state_of(p), trial_state_.data() + static_cast<std::size_t>(p) * pts.state_stride,
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
      if (model_.axisymmetric) {  // d(eta_r / r) / d eta_a at r_n+1 (finite strain) or r_n
        const double r = pts.position[p][0] * (mat.finite_strain() ? dF(2, 2) : 1.0);
        for (int a = 0; a < s.count; ++a) hoop_[p][a] = s.N[a] / r;
      }
    }
    if (split_) lowest_over_ranks(inverted, inverted_det);  // every rank fails, or none
    if (inverted < kNone) throw StepFailure{fmt::format("point {} inverted (det dF = {:.3g})", inverted, inverted_det)};
    scatter_internal_force(du, f_int);
  }

  /// f_int,i = sum_p w_p stress_p grad N_i, by buckets of points with disjoint nodes; then
  /// the penalty terms at the iterate du (rigid-box contacts of the points, then, on the
  /// ranks' sum, the ghost faces), which act as internal forces of the grid.
  void scatter_internal_force(const Vector& du, Vector& f_int) {
    // The points of a run share their stencil nodes: their sum is scattered once.
    assembler_.for_each_run([&](const int* first, const int* last) {
      const Stencil<dim>& s = st_[*first];
      std::array<Vec<dim>, Stencil<dim>::capacity> f;
      for (int a = 0; a < s.count; ++a) f[a].setZero();
      for (const int* q = first; q != last; ++q) {
        const auto& G = grads_[*q];
        const Mat3& stress = response_[*q].stress;
        const double w = weights_[*q];
        for (int a = 0; a < s.count; ++a)
          for (int i = 0; i < dim; ++i) {
            double v = 0.0;
            for (int j = 0; j < dim; ++j) v += stress(i, j) * G[a][j];
            f[a][i] += w * v;
          }
        if (model_.axisymmetric)  // the hoop stress on the virtual hoop strain eta_r / r
          for (int a = 0; a < s.count; ++a) f[a][0] += w * stress(2, 2) * hoop_[*q][a];
      }
      for (int a = 0; a < s.count; ++a)
        for (int i = 0; i < dim; ++i) f_int[dofs_.dof(s.node[a], i)] += f[a][i];
    });
    if (contact_) contact_->add_force(du, f_int);
    for (const NodeTie& t : active_ties_) {
      const int a = dofs_.dof(t.a, t.component), b = dofs_.dof(t.b, t.component);
      const double f = t.stiffness * (du[a] - du[b]);
      f_int[a] += f;
      f_int[b] -= f;
    }
    if (ghost_) ghost_->add_force(dofs_, du, f_int);  // this rank's faces (GhostFaces), as in K
    halo_.sum(f_int);  // the ranks' shares, in this rank's own and ghost rows
  }

  /// The tangent K at the state of the last internal_force(): each point's material
  /// tangent is formed inside the (threaded, by strips) scatter-add, never stored. With a
  /// symmetric tangent (A_ijkl = A_klij) only the blocks b <= a are formed and mirrored.
  /// In a distributed run K is this rank's share (`share` must be true), which the solver
  /// adds up: its points' terms and their contacts, and its ghost faces'.
  /// Its pattern holds those couplings only (make_pattern()). K is the step's own matrix,
  /// assembled in place (no copy of the pattern per Newton solve: 36 MB at 1e5 dof in 2D),
  /// for the caller to eliminate constraints in and factorise; the next call assembles it
  /// afresh.
  SparseMatrix& stiffness(bool share = false) {
    if (split_ && !share)
      throw std::logic_error("a distributed run's tangent is each rank's share; its solver must add the shares up");
    SparseMatrix& K = tangent_;
    if (assembled_) {  // zeroed on the threads (a serial fill was 3-4 ms per iteration at 1e5 dof in 2D)
      double* values = K.valuePtr();
      const long n = static_cast<long>(K.nonZeros());
#pragma omp parallel for schedule(static) if (use_threads(K.rows()))
      for (long k = 0; k < n; ++k) values[k] = 0.0;
    }
    assembled_ = true;
    if (fbar_) fbar_q_.resize(grads_.size());
    const bool symmetric = model_.symmetric_tangent();
    assembler_.add_matrix(
        K,
        [&](int p, const Stencil<dim>& s, typename Assembler<dim>::LocalMatrix& Ke) {
          // K_(a i)(b k) = w sum_j G_aj (sum_l A_ijkl G_bl): the inner sum once per node b.
          const auto& G = grads_[p];
          Mat9 A;
          // (axisymmetric: the hoop entries, index 2, too)
          model_.materials[model_.points.material[p]]->tangent(response_[p], model_.axisymmetric ? 3 : dim, A);
          if (fbar_) fbar_local_tangent<dim>(response_[p].stress, A, fbar_q_[p], model_.axisymmetric ? 3 : dim);
          const double w = weights_[p];
          if (model_.axisymmetric) return add_hoop_tangent(s, G, hoop_[p], A, w, symmetric, Ke);
          for (int b = 0; b < s.count; ++b) {
            double H[dim][dim][dim];  // H[i][j][k] = sum_l A_ijkl G_bl
            for (int i = 0; i < dim; ++i)
              for (int j = 0; j < dim; ++j)
                for (int k = 0; k < dim; ++k) {
                  double v = 0.0;
                  for (int l = 0; l < dim; ++l) v += A(3 * i + j, 3 * k + l) * G[b][l];
                  H[i][j][k] = w * v;
                }
            for (int a = symmetric ? b : 0; a < s.count; ++a)
              for (int i = 0; i < dim; ++i)
                for (int k = 0; k < dim; ++k) {
                  double v = 0.0;
                  for (int j = 0; j < dim; ++j) v += G[a][j] * H[i][j][k];
                  Ke(a * dim + i, b * dim + k) += v;
                }
          }
        },
        symmetric);
    if (fbar_)
      fbar_->add_coupling(K, all_cells_, st_, dofs_, grads_, weights_, fbar_q_, fbar_dJ_, fbar_dJbar_,
                          model_.axisymmetric ? &hoop_ : nullptr);
    if (ghost_) ghost_->add_matrix(dofs_, K);  // this rank's faces
    if (contact_) contact_->add_matrix(K);
    for (const NodeTie& t : active_ties_) {
      const int a = dofs_.dof(t.a, t.component), b = dofs_.dof(t.b, t.component);
      K.valuePtr()[pattern_offset(K, a, a)] += t.stiffness;
      K.valuePtr()[pattern_offset(K, b, b)] += t.stiffness;
      K.valuePtr()[pattern_offset(K, a, b)] -= t.stiffness;
      K.valuePtr()[pattern_offset(K, b, a)] -= t.stiffness;
    }
    return K;
  }

  /// The consistent mass matrix M_(ai)(bk) = sum_p N_a N_b m_p delta_ik of this rank's
  /// points, in the tangent's pattern (a dynamic step's inertia, mpm/Dynamics.hpp).
  SparseMatrix consistent_mass() const {
    SparseMatrix M = tangent_;
    std::fill(M.valuePtr(), M.valuePtr() + M.nonZeros(), 0.0);
    assembler_.add_matrix(
        M,
        [&](int p, const Stencil<dim>& s, typename Assembler<dim>::LocalMatrix& Ke) {
          const double m = model_.points.mass[p];
          for (int b = 0; b < s.count; ++b)
            for (int a = b; a < s.count; ++a)
              for (int i = 0; i < dim; ++i) Ke(a * dim + i, b * dim + i) += m * s.N[a] * s.N[b];
        },
        true);
    return M;
  }

  /// Eq. (2): maps the converged increment to the points and updates their state. Each
  /// point's update reads and writes its own entries only: on the threads (serially 0.02 s
  /// per step for 2e5 points in 2D).
  void commit(Model<dim>& m, const Vector& du) {
    auto& pts = m.points;
    pts.state = trial_state_;  // the material histories of the converged iterate
    if (contact_) contact_->store_shear(pts.contact_shear);  // (frictional boxes' stick)
    const int np = pts.size();
#pragma omp parallel for schedule(static) if (use_threads(np))
    for (int p = 0; p < np; ++p) {
      Vec<dim> dx;
      const Mat3 g = point_increment(p, du, &dx);
      const bool finite = m.material_of(p).finite_strain();
      pts.work[p] +=
          step_work(pts, p, material_increment(p, Mat3::Identity() + g), response_[p].stress, finite, fbar_ != nullptr);
      pts.position[p] += dx;
      pts.F[p] = (Mat3::Identity() + g) * pts.F[p];
      const double J = pts.F[p].determinant();
      pts.volume[p] = J * pts.original_volume[p];
      const MaterialResponse& r = response_[p];
      if (fbar_) {  // sigma = tau(Fbar) / Jbar
        pts.fbar_jacobian[p] *= fbar_dJbar_[p];
        pts.stress[p] = r.stress / pts.fbar_jacobian[p];
      } else {
        pts.stress[p] = finite ? Mat3(r.stress / J) : r.stress;
      }
      if (m.basis == BasisKind::CPGIMP)
        for (int d = 0; d < dim; ++d) pts.half_length[p][d] = pts.original_half_length[p][d] * pts.F[p].col(d).norm();
    }
  }

  /// After commit: frees what only Newton needed, keeping stencils and equation numbers.
  void release_newton_data() {
    tangent_ = SparseMatrix();
    assembled_ = false;
    decltype(response_)().swap(response_);
    std::vector<double>().swap(trial_state_);
    std::vector<std::array<Vec<dim>, Stencil<dim>::capacity>>().swap(grads_);
    std::vector<std::array<double, Stencil<dim>::capacity>>().swap(hoop_);
    std::vector<double>().swap(weights_);
  }

  /// At a converged iterate: keeps the reactions f_int - f_ext (a distributed run's right
  /// in own and ghost rows); a distributed run sums the boxes' contact forces over the ranks.
  void converged() override {
    reaction_ = f_int_ - f_ext_;
    if (split_ && contact_) contact_->sum_forces_over_ranks();
  }
  /// Adds f to the reactions (a dynamic step's inertia and damping forces).
  void add_to_reactions(const Vector& f) { reaction_ += f; }

  /// The step's grid fields for the outputs, at every grid node or (a distributed run's)
  /// at the nodes listed.
  struct GridFields {
    Vector displacement;  ///< the increment du, dim per node (zero on inactive nodes)
    Vector reaction;      ///< f_int - f_ext at the converged iterate, dim per node
    Vector mass;          ///< sum_p N_i m_p (eq. 1), one per node
    /// The grid nodes the values are at, ascending (value k at nodes[k]); empty: every
    /// grid node, in order.
    std::vector<int> nodes;
  };
  /// `du`: the converged increment (a distributed run's right in own and ghost rows).
  /// Serially at every node. A distributed run's are at the active nodes this rank knows
  /// only (its local equations: no array as long as the grid), right at the nodes it owns
  /// (Model::rank_boxes) and at the corners of its cells (its piece of the grid's VTU;
  /// an inactive corner is not listed), and not used elsewhere: the masses are summed in
  /// own and ghost rows, then the corners' rows that other ranks own are fetched from them
  /// (a neighbour exchange, no whole-grid gather; a corner of an empty cell may be in no
  /// point's stencil of this rank). A collective call in a distributed run.
  GridFields grid_fields(const Vector& du) const {
    const int nn = model_.grid.num_nodes();
    if (!split_) return {dofs_.to_grid_all(du), dofs_.to_grid_all(reaction_), nodal_mass(st_, model_.points, nn), {}};
    Vector mass = mass_;  // (the points may have moved to other ranks since: their masses as the step began)
    halo_.sum(mass);
    Vector displacement = du, reaction = reaction_;
    const RowHalo piece(dofs_.rank_rows(), piece_rows(), dofs_.global_rows());
    for (Vector* v : {&displacement, &reaction, &mass}) piece.fetch_ghosts(*v);
    std::vector<std::pair<int, int>> by_node(dofs_.num_active_nodes());  // (node, local equation)
    for (int e = 0; e < dofs_.num_active_nodes(); ++e) by_node[e] = {dofs_.node_of(e), e};
    std::sort(by_node.begin(), by_node.end());
    const Eigen::Index k = static_cast<Eigen::Index>(by_node.size());
    GridFields out{Vector(k * dim), Vector(k * dim), Vector(k), std::vector<int>(k)};
    for (Eigen::Index j = 0; j < k; ++j) {
      const auto [n, e] = by_node[j];
      out.nodes[j] = n;
      for (int i = 0; i < dim; ++i) {
        out.displacement[j * dim + i] = displacement[dofs_.dof(n, i)];
        out.reaction[j * dim + i] = reaction[dofs_.dof(n, i)];
      }
      out.mass[j] = mass[dofs_.dof(n, 0)];
    }
    return out;
  }
  /// The force of each rigid box on the body at the converged iterate (dim per box).
  Vector rigid_forces() const {
    Vector f = Vector::Zero(static_cast<Eigen::Index>(model_.rigid_boxes.size()) * dim);
    for (std::size_t b = 0; contact_ && b < model_.rigid_boxes.size(); ++b)
      for (int i = 0; i < dim; ++i) f[b * dim + i] = contact_->force(static_cast<int>(b))[i];
    return f;
  }

 private:
  /// How far beyond its box of nodes a rank learns the equations (DofMap's margin, in
  /// node layers): three, which hold the corners of the cells beside its own (the ghost
  /// penalty's faces whose lowest node is its, its grid piece's corners); its stencils'
  /// nodes it learns wherever they are.
  static constexpr int ghost_margin = 3;

  /// A distributed run's: the (local) rows of the active corners of this rank's cells, ascending.
  std::vector<int> piece_rows() const {
    const auto& grid = model_.grid;
    std::vector<int> rows;
    model_.rank_boxes.for_each_cell(ranks::rank(), [&](int key) {
      const auto c = grid.node_ijk(key);
      for (int k = 0; k < (1 << dim); ++k) {
        auto ijk = c;
        for (int d = 0; d < dim; ++d) ijk[d] += (k >> d) & 1;
        const int n = grid.node_index(ijk);
        if (dofs_.active(n))
          for (int i = 0; i < dim; ++i) rows.push_back(dofs_.dof(n, i));
      }
    });
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    return rows;
  }

  /// The couplings of the tangent: each point's stencil (with F-bar, each cell's points'
  /// stencils together) and each ghost face's nodes. In a distributed run, those of this
  /// rank's share (stiffness()): its points' (its cells'), its ghost faces' (GhostFaces:
  /// those whose lowest node is in its run), and the diagonal block of each constrained node in its rows (DirichletElimination
  /// puts a constrained diagonal in the share of the row's owner). PETSc adds the
  /// shares' patterns up.
  SparseMatrix make_pattern() const {
    const int n_main = fbar_ ? static_cast<int>(fbar_->nodes().size()) : static_cast<int>(st_.size());
    const int n_ghost = ghost_ ? ghost_->size() : 0;
    std::vector<int> constrained_nodes;
    if (split_) {  // those in this rank's rows (a constrained node its points may not reach)
      const int first = dofs_.own_nodes_first() * dim, last = dofs_.own_nodes_last() * dim;
      for (const int dof : constrained_)
        if (dof >= first && dof < last) constrained_nodes.push_back(dofs_.node_of(dof / dim));
      std::sort(constrained_nodes.begin(), constrained_nodes.end());
      constrained_nodes.erase(std::unique(constrained_nodes.begin(), constrained_nodes.end()), constrained_nodes.end());
    }
    const int n_fixed = static_cast<int>(constrained_nodes.size());
    const int n_ties = static_cast<int>(active_ties_.size());
    return build_pattern_of_groups(
        n_main + n_ghost + n_fixed + n_ties,
        [&](int g) {
          if (g >= n_main + n_ghost + n_fixed) return 2;
          if (g >= n_main + n_ghost) return 1;
          if (g >= n_main) return ghost_->faces()[g - n_main].count;
          return fbar_ ? static_cast<int>(fbar_->nodes()[g].size()) : st_[g].count;
        },
        [&](int g, int a) {
          if (g >= n_main + n_ghost + n_fixed) {
            const NodeTie& t = active_ties_[g - n_main - n_ghost - n_fixed];
            return a == 0 ? std::min(t.a, t.b) : std::max(t.a, t.b);
          }
          if (g >= n_main + n_ghost) return constrained_nodes[g - n_main - n_ghost];
          if (g >= n_main) return ghost_->faces()[g - n_main].node[a];
          return fbar_ ? fbar_->nodes()[g][a] : st_[g].node[a];
        },
        dofs_);
  }

  /// The points' stencils at x_n. With F-bar, without the nodes they reach only by a
  /// sliver (drop_weak_nodes: support below 1e-8 of a cell's volume): F-bar takes the
  /// volumetric stiffness a lone point gives such a node away, and the tangent turned
  /// singular there (docs/plasticity.md). Without F-bar the stencils are untouched.
  /// `ids`: a distributed run's (the supports and failures of every rank's points).
  static PointStencils<dim> stencils(const Model<dim>& m, const std::vector<int>* ids) {
    PointStencils<dim> st = evaluate_stencils(m.grid, m.points, m.basis, ids);
    if (m.fbar)
      drop_weak_nodes(st, m.points, m.grid.num_nodes(), m.grid.cell_size().prod(), 1e-8, ids ? &m.rank_boxes : nullptr);
    return st;
  }

  /// internal_force with F-bar (mpm/FBar.hpp): dJ of every point, dJbar of its cell, the
  /// update with dFbar, gradients of the actual dF, weights (v_n / Jbar_n) dJ / dJbar.
  void internal_force_fbar(const Vector& du, Vector& f_int) {
    const auto& pts = model_.points;
    const int np = pts.size();
    f_int = Vector::Zero(dofs_.num_dofs());
    grads_.resize(np);
    weights_.resize(np);
    if (model_.axisymmetric) hoop_.resize(np);
    auto [inverted, det] = volume_changes(du);
    if (split_) lowest_over_ranks(inverted, det);  // every rank fails, or none
    if (inverted < kNone) throw StepFailure{fmt::format("point {} inverted (det dF = {:.3g})", inverted, det)};
#pragma omp parallel for schedule(static) if (use_threads(np))
    for (int p = 0; p < np; ++p) {
      const Stencil<dim>& s = st_[p];
      model_.material_of(p).update(material_increment(p, fbar_dF_[p]), pts.state_of(p),
                                   trial_state_.data() + static_cast<std::size_t>(p) * pts.state_stride, response_[p]);
      const Mat3 inv = fbar_dF_[p].inverse();
      auto& G = grads_[p];
      for (int a = 0; a < s.count; ++a)
        for (int l = 0; l < dim; ++l) {
          double v = 0.0;
          for (int m = 0; m < dim; ++m) v += s.dN[a][m] * inv(m, l);
          G[a][l] = v;
        }
      weights_[p] = pts.volume[p] / pts.fbar_jacobian[p] * fbar_dJ_[p] / fbar_dJbar_[p];
      if (model_.axisymmetric)  // the virtual hoop strain at r_n+1, as without F-bar
        for (int a = 0; a < s.count; ++a) hoop_[p][a] = s.N[a] / (pts.position[p][0] * fbar_dF_[p](2, 2));
    }
    scatter_internal_force(du, f_int);
  }

  /// F-bar: dF and dJ of every point and dJbar of every cell; the lowest inverted point
  /// (its id; kNone if none) and its dJ.
  std::pair<int, double> volume_changes(const Vector& du) {
    const int np = model_.points.size();
    fbar_dF_.resize(np);
    fbar_dJ_.resize(np);
    int inverted = kNone;
    double det = 0.0;
    for (int p = 0; p < np; ++p) {
      fbar_dF_[p] = Mat3::Identity() + point_increment(p, du);
      fbar_dJ_[p] = fbar_dF_[p].determinant();
      if (!(fbar_dJ_[p] > 0.0) && id(p) < inverted) {
        inverted = id(p);
        det = fbar_dJ_[p];
      }
    }
    fbar_->average(fbar_dJ_, fbar_dJbar_, nullptr);
    return {inverted, det};
  }

  /// grad_n du at point p (increment_gradient), with the hoop component du_r / r_n when
  /// axisymmetric; `dx`: the point's displacement.
  Mat3 point_increment(int p, const Vector& du, Vec<dim>* dx = nullptr) const {
    Vec<dim> u;
    Mat3 g = increment_gradient(st_[p], dofs_, du, model_.axisymmetric || dx ? &u : nullptr);
    if (model_.axisymmetric) g(2, 2) = u[0] / model_.points.position[p][0];
    if (dx) *dx = u;
    return g;
  }

  /// One point's axisymmetric tangent: K_(a i)(b k) = w grad eta : A : grad du over the
  /// 3 x 3 gradients of the nodes' unit displacements, in-plane G (i, j < 2) and the hoop
  /// entry (2, 2) = hoop_a of a radial one (as the 3D tangent of a field without torsion).
  /// Each gradient has 2 or 3 entries: A times it is 9 x 3 products, not 81.
  static void add_hoop_tangent(const Stencil<dim>& s, const std::array<Vec<dim>, Stencil<dim>::capacity>& G,
                               const std::array<double, Stencil<dim>::capacity>& hoop, const Mat9& A, double w,
                               bool symmetric, typename Assembler<dim>::LocalMatrix& Ke) {
    for (int b = 0; b < s.count; ++b)
      for (int k = 0; k < dim; ++k) {
        double AB[9];  // w A : grad(du of node b, component k)
        for (int r = 0; r < 9; ++r) {
          double v = 0.0;
          for (int l = 0; l < dim; ++l) v += A(r, 3 * k + l) * G[b][l];
          if (k == 0) v += A(r, 8) * hoop[b];
          AB[r] = w * v;
        }
        for (int a = symmetric ? b : 0; a < s.count; ++a)
          for (int i = 0; i < dim; ++i) {
            double v = 0.0;
            for (int j = 0; j < dim; ++j) v += G[a][j] * AB[3 * i + j];
            if (i == 0) v += hoop[a] * AB[8];
            Ke(a * dim + i, b * dim + k) += v;
          }
      }
  }

  /// Point p's number in the whole body (a distributed run's points are a subset).
  int id(int p) const { return split_ ? ids_[p] : p; }
  static constexpr int kNone = std::numeric_limits<int>::max();  ///< no failed point

  const Model<dim>& model_;
  bool split_;            ///< distributed: model_'s points are this rank's
  std::vector<int> ids_;  ///< distributed: the ids of model_'s points in the whole body
  PointStencils<dim> st_;
  std::unique_ptr<FBarCells<dim>> fbar_;
  DofMap dofs_;
  std::vector<int> all_cells_;                  ///< F-bar: 0, 1, ... (every cell of the points)
  std::unique_ptr<GhostFaces<dim>> ghost_;      ///< ghost penalty faces (mpm/GhostPenalty.hpp); null when off
  std::unique_ptr<RigidContact<dim>> contact_;  ///< rigid boxes' contacts (mpm/RigidContact.hpp); null without
  std::vector<NodeTie> active_ties_;            ///< Model::ties between active nodes
  std::vector<Mat3> fbar_dF_, fbar_q_;
  std::vector<double> fbar_dJ_, fbar_dJbar_;
  /// make_pattern()'s, zero until stiffness() assembles the tangent in it
  SparseMatrix tangent_;
  bool assembled_ = false;  ///< tangent_ holds a tangent (stiffness() zeroes it first)
  RowHalo halo_;            ///< distributed: own and ghost rows (serially: every row, no exchange)
  Assembler<dim> assembler_;
  std::vector<int> constrained_;
  std::vector<double> increments_;
  std::vector<double> totals_;  ///< the prescribed values per unit load factor (constrained_'s order)
  Vector f_ref_;                ///< eq. (1) at load factor 1 (made when the arc-length method asks)
  double largest_increment_ = 0.0;
  Vector f_ext_;
  Vector f_dead_;  ///< a dead gravity's share of f_ext (empty: everything scales with lambda)
  Vector f_int_;  ///< at the last residual()'s iterate
  /// Written by every internal_force() before it is read: not zeroed when made (2e5
  /// points: 40 MB, 4 ms of a load step's set-up).
  std::vector<MaterialResponse, DefaultInitAllocator<MaterialResponse>> response_;
  std::vector<double> trial_state_;  ///< the state block of the current iterate
  Vector reaction_;                  ///< f_int - f_ext at the converged iterate
  Vector mass_;  ///< distributed: this rank's points' nodal masses in the first component's rows
  /// The gradients of the points' shape functions in the configuration their stress lives
  /// in, and their weights.
  std::vector<std::array<Vec<dim>, Stencil<dim>::capacity>> grads_;
  std::vector<double> weights_;
  /// Axisymmetric: each point's N_a / r (at r_n+1 for finite strain, r_n for small).
  std::vector<std::array<double, Stencil<dim>::capacity>> hoop_;
};

}  // namespace gradmpm::detail
