#pragma once
// One load step of regularised softening plasticity solved monolithically: the load step's
// displacements du and the nonlocal plastic strain kappa_bar at the same grid nodes, by one
// Newton iteration on both (`[regularisation] coupling = "monolithic"`; docs/shear-bands.md).
// The staggered scheme of mpm/ImplicitGradient.hpp solves the same two equations in turn.
// Internal to the driver (mpm/QuasiStatic.cpp).
//
// Unknowns per active node: du (dim) and the increment dk of kappa_bar over its start
// kappa_bar_0, the smoothing of kappa_n (NonlocalPlasticStrain::nodal). At a regularised
// point kappa_bar_p = sum_a N_a kappa_bar_a over its regularised stencil (the weak nodes
// left out, as in the staggered scheme), written into the state the step starts from,
// where the law reads it. The equations:
//   momentum:  f_ext - f_int(du, kappa_bar) = 0
//   nonlocal:  omega sum_p V_p [N_a (kappa_p - kappa_bar_p) - l^2 grad N_a . grad kappa_bar_p] = 0
// (the Helmholtz equation (M + l^2 L) kappa_bar = sum_p N kappa_p V_p, integrated by the
// regularised points at x_n), kappa_p the law's equivalent plastic strain at the iterate.
// The nonlocal rows are scaled by omega = E / h (forces per unit of V kappa), so that
// Newton's residual weighs both fields alike. Nodes no regularised point reaches keep
// kappa_bar = 0 (constrained). The consistent tangent is
//   [ K_uu                          sum_p w_p (dtau_p/dkbar) G_a N_b                    ]
//   [ -omega sum_p V_p N_a dkappa_p/du    omega (M + l^2 L - sum_p V_p N_a dkappa_p/dkbar N_b) ]
// with K_uu the load step's (each law's consistent tangent at frozen kappa_bar). The
// sensitivities of a plastic point's return, dtau/dkbar, dkappa/dkbar and dkappa/d(dF),
// are central differences of the law's own update (2 + 2 dim^2 updates per plastic point
// and iteration): every regularised law (von Mises, Drucker-Prager, Mohr-Coulomb, with
// their apex, corner and floor branches) gives them without a derivative of its own.
// With F-bar the point's law sees dFbar = (dJbar_c / dJ)^(1/dim) dF, and dkappa/du takes
// the cell's volume change too (the cell terms, as the load step's F-bar coupling).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "gradmpm/core/Parallel.hpp"
#include "gradmpm/mpm/ImplicitGradient.hpp"
#include "gradmpm/mpm/LoadStep.hpp"
#include "gradmpm/mpm/NodeBlocks.hpp"

namespace gradmpm::detail {

template <int dim>
class GradientCouplingStep final : public NonlinearProblem {
 public:
  static constexpr int nc = dim + 1;  ///< components per node: du and dk

  GradientCouplingStep(LoadStep<dim>& step, Model<dim>& model, const NonlocalPlasticStrain<dim>& nonlocal)
      : step_(step),
        model_(model),
        nonlocal_(nonlocal),
        dofs_(step.stencils(), model.grid.num_nodes(), nc),
        assembler_(step.stencils(), model.points, dofs_, &model.grid),
        l2_(model.regularisation.length_scale * model.regularisation.length_scale) {
    if (ranks::distributed()) throw std::logic_error("the monolithic gradient coupling runs on one rank");
    omega_ = stiffest_young(model.materials) / model.grid.cell_size().minCoeff();
    tangent_ = grown_pattern<dim, nc>(step.pattern(), step.dofs().num_active_nodes());
    regularised_entries();
    helmholtz_block();
    start_values();
    constraints();
  }

  const DofMap& dofs() const override { return dofs_; }
  const RowHalo& halo() const override { return halo_; }
  Eigen::MatrixXd node_coordinates() const override { return dofs_.coordinates(model_.grid); }
  const std::vector<int>& constrained() const override { return constrained_; }
  const std::vector<double>& increments() const override { return increments_; }
  double largest_increment() const override { return step_.largest_increment(); }
  const SparseMatrix& pattern() const override { return tangent_; }
  bool symmetric_tangent() const override { return false; }
  double roundoff_force() const override { return step_.roundoff_force(); }

  ResidualNorms residual(const Vector& x, Vector& r) override {
    split_node_blocks<dim>(x, du_, dk_);
    write_nonlocal();
    Vector r_u;
    const ResidualNorms solid = step_.residual(du_, r_u);
    const auto& st = step_.stencils();
    const auto& pts = model_.points;
    const std::vector<double>& trial = step_.trial_state();
    r = Vector::Zero(dofs_.num_dofs());
    Vector load = Vector::Zero(dofs_.num_active_nodes());  // omega sum_p N V kappa: the rows' scale
    assembler_.for_each_point_disjoint([&](int p) {
      if (!kept_[p]) return;
      const Stencil<dim>& s = st[p];
      const double V = pts.volume[p];
      const double kappa = trial[static_cast<std::size_t>(p) * pts.state_stride + kappa_slot(p)];
      for (int a = 0; a < s.count; ++a) {
        if (!kept(p, a)) continue;
        const int e = dofs_.dof(s.node[a], 0) / nc;
        load[e] += omega_ * V * s.N[a] * kappa;
        r[e * nc + dim] += omega_ * V * (s.N[a] * (kappa - kbar_[p]) - l2_ * s.dN[a].dot(grad_kbar_[p]));
      }
    });
    for (int e = 0; e < dofs_.num_active_nodes(); ++e)
      for (int i = 0; i < dim; ++i) r[e * nc + i] = r_u[e * dim + i];
    for (int c : constrained_) r[c] = 0.0;
    const double scale = std::isfinite(solid.scale) ? std::max(solid.scale, load.norm()) : solid.scale;
    return {r.norm(), scale};
  }

  SparseMatrix& tangent(bool /*share*/) override {
    const SparseMatrix& K = step_.tangent(false);
    std::copy(helmholtz_.begin(), helmholtz_.end(), tangent_.valuePtr());
    add_node_blocks<dim, nc>(K, tangent_);
    sensitivities();
    const auto& st = step_.stencils();
    const auto& pts = model_.points;
    for (int p = 0; p < pts.size(); ++p)
      if (plastic_[p] >= 0) add_plastic_point(p, st[p], sens_[plastic_[p]], pts.volume[p]);
    if (step_.fbar_cells()) add_cell_terms();
    return tangent_;
  }

  void converged() override { step_.converged(); }

  /// After convergence: kappa_bar of the converged x in the points' state (as the
  /// committed states will hold it); returns the displacement part of x (for LoadStep::commit).
  Vector commit(const Vector& x) {
    split_node_blocks<dim>(x, du_, dk_);
    write_nonlocal();
    return du_;
  }

 private:
  /// A plastic point's return's sensitivities at the iterate.
  struct Sensitivity {
    Mat3 dtau_dkbar = Mat3::Zero();  ///< of the stress its law returns
    double dkappa_dkbar = 0.0;
    std::array<Vec<dim>, Stencil<dim>::capacity> dkappa_du;  ///< per stencil node and component (the point's own dF)
    double cell = 0.0;  ///< F-bar: dkappa/du through the cell, cell * sum_q beta_q G_q . du_q
  };

  bool kept(int p, int a) const { return (kept_[p] >> a) & 1u; }

  /// omega (M + l^2 L) in the kappa_bar rows, constant over the step's iterations.
  void helmholtz_block() {
    const auto& pts = model_.points;
    assembler_.add_matrix(tangent_, [&](int p, const Stencil<dim>& s, typename Assembler<dim, nc>::LocalMatrix& Ke) {
      if (!kept_[p]) return;
      const double w = omega_ * pts.volume[p];
      for (int b = 0; b < s.count; ++b)
        for (int a = 0; a < s.count; ++a)
          if (kept(p, a) && kept(p, b)) Ke(a * nc + dim, b * nc + dim) += w * (s.N[a] * s.N[b] + l2_ * s.dN[a].dot(s.dN[b]));
    });
    helmholtz_.assign(tangent_.valuePtr(), tangent_.valuePtr() + tangent_.nonZeros());
  }

  /// A plastic point's coupling terms: sum_p w_p (dtau/dkbar) G_a N_b, -omega V_p N_a
  /// dkappa/du and -omega V_p N_a dkappa/dkbar N_b, added into the node blocks of its
  /// stencil (a node block's nc rows lie together in each of its columns: grown_pattern).
  void add_plastic_point(int p, const Stencil<dim>& s, const Sensitivity& d, double V) {
    const auto& G = step_.gradients(p);
    const double w = step_.weight(p);
    double* values = tangent_.valuePtr();
    const int* outer = tangent_.outerIndexPtr();
    for (int b = 0; b < s.count; ++b) {
      const int col = dofs_.dof(s.node[b], 0);
      for (int a = 0; a < s.count; ++a) {
        const int at = pattern_offset(tangent_, dofs_.dof(s.node[a], 0), col) - outer[col];
        auto entry = [&](int i, int k) -> double& { return values[outer[col + k] + at + i]; };
        if (kept(p, b))  // d f_int,ai / d kbar_b
          for (int i = 0; i < dim; ++i) {
            double v = 0.0;
            for (int j = 0; j < dim; ++j) v += d.dtau_dkbar(i, j) * G[a][j];
            entry(i, dim) += w * v * s.N[b];
          }
        if (!kept(p, a)) continue;
        for (int k = 0; k < dim; ++k) entry(dim, k) -= omega_ * V * s.N[a] * d.dkappa_du[b][k];
        if (kept(p, b)) entry(dim, dim) -= omega_ * V * d.dkappa_dkbar * s.N[a] * s.N[b];
      }
    }
  }
  int kappa_slot(int p) const { return nonlocal_.kappa_slot(model_.points.material[p]); }
  int nonlocal_slot(int p) const { return nonlocal_.nonlocal_slot(model_.points.material[p]); }

  /// Which entries of each point's stencil carry kappa_bar: those of its regularised
  /// stencil (NonlocalPlasticStrain::stencils(), a subsequence of the step's).
  void regularised_entries() {
    const auto& st = step_.stencils();
    const auto& rs = nonlocal_.stencils();
    static_assert(Stencil<dim>::capacity <= 32, "a stencil's entries fit a 32-bit mask");
    kept_.assign(st.size(), 0u);
    for (std::size_t p = 0; p < st.size(); ++p)
      for (int a = 0, k = 0; a < st[p].count && k < rs[p].count; ++a)
        if (st[p].node[a] == rs[p].node[k]) {
          kept_[p] |= 1u << a;
          ++k;
        }
    kbar_.assign(st.size(), 0.0);
    grad_kbar_.assign(st.size(), Vec<dim>::Zero());
    plastic_.assign(st.size(), -1);
  }

  /// kappa_bar_0 at the active nodes: the smoothing of kappa_n (zero where no regularised
  /// point reaches).
  void start_values() {
    const DofMap& scalar = nonlocal_.dofs();
    const Vector nodal = nonlocal_.nodal(model_.points.state);
    kbar0_ = Vector::Zero(dofs_.num_active_nodes());
    held_.assign(dofs_.num_active_nodes(), false);
    for (int e = 0; e < dofs_.num_active_nodes(); ++e) {
      const int node = dofs_.node_of(e);
      if (!scalar.active(node)) continue;
      kbar0_[e] = nodal[scalar.dof(node, 0)];
      held_[e] = true;
    }
  }

  /// The solid's constraints in the combined numbering, and kappa_bar held at the nodes
  /// outside the Helmholtz system.
  void constraints() {
    std::vector<std::pair<int, double>> outside;
    for (int e = 0; e < dofs_.num_active_nodes(); ++e)
      if (!held_[e]) outside.push_back({e * nc + dim, 0.0});
    node_block_constraints<dim>(step_.constrained(), step_.increments(), std::move(outside), constrained_, increments_);
  }

  /// kappa_bar and its gradient at the regularised points for the iterate's dk, written
  /// into the state the step starts from (the laws read it there).
  void write_nonlocal() {
    const auto& st = step_.stencils();
    auto& pts = model_.points;
    for (std::size_t p = 0; p < st.size(); ++p) {
      if (!kept_[p]) continue;
      double v = 0.0;
      Vec<dim> grad = Vec<dim>::Zero();
      for (int a = 0; a < st[p].count; ++a) {
        if (!kept(static_cast<int>(p), a)) continue;
        const int e = dofs_.dof(st[p].node[a], 0) / nc;
        const double k = kbar0_[e] + dk_[e];
        v += st[p].N[a] * k;
        grad += st[p].dN[a] * k;
      }
      kbar_[p] = v;
      grad_kbar_[p] = grad;
      pts.state[p * pts.state_stride + nonlocal_slot(static_cast<int>(p))] = v;
    }
  }

  /// The sensitivities of every regularised point that is plastic at the iterate (its
  /// kappa above kappa_n), by central differences of its law's update.
  void sensitivities() {
    const auto& pts = model_.points;
    const std::vector<double>& trial = step_.trial_state();
    std::vector<int> plastic;
    for (int p = 0; p < pts.size(); ++p) {
      plastic_[p] = -1;
      if (!kept_[p]) continue;
      const std::size_t k = static_cast<std::size_t>(p) * pts.state_stride + kappa_slot(p);
      if (trial[k] > pts.state[k]) {
        plastic_[p] = static_cast<int>(plastic.size());
        plastic.push_back(p);
      }
    }
    sens_.resize(plastic.size());
    const int n = static_cast<int>(plastic.size());
#pragma omp parallel if (use_threads(n))
    {
      std::vector<double> state_n(pts.state_stride), state(pts.state_stride);
#pragma omp for schedule(static)
      for (int j = 0; j < n; ++j) sens_[j] = sensitivity(plastic[j], state_n, state);
    }
  }

  Sensitivity sensitivity(int p, std::vector<double>& state_n, std::vector<double>& state) const {
    const auto& pts = model_.points;
    const Stencil<dim>& s = step_.stencils()[p];
    const Material& mat = model_.material_of(p);
    const bool fbar = step_.fbar_cells() != nullptr;
    const int ks = kappa_slot(p), ns = nonlocal_slot(p);
    std::copy(pts.state_of(p), pts.state_of(p) + pts.state_stride, state_n.begin());
    const Mat3 g = increment_gradient(s, step_.dofs(), du_);
    const Mat3 dF = Mat3::Identity() + g;
    // The argument the load step's update takes: g, or with F-bar the modified dF.
    const Mat3 arg = fbar ? step_.material_increment(p, dF) : g;
    MaterialResponse r;
    auto update = [&](const Mat3& a, double& kappa, Mat3& tau) {
      if (fbar)
        mat.update(a, state_n.data(), state.data(), r);
      else
        mat.update_increment(a, state_n.data(), state.data(), r);
      kappa = state[ks];
      tau = r.stress;
    };
    Sensitivity d;
    double kp, km;
    Mat3 tp, tm;
    const double kbar = state_n[ns];
    const double hk = kStep * std::max(1.0, std::abs(kbar));
    state_n[ns] = kbar + hk;
    update(arg, kp, tp);
    state_n[ns] = kbar - hk;
    update(arg, km, tm);
    state_n[ns] = kbar;
    d.dkappa_dkbar = (kp - km) / (2.0 * hk);
    d.dtau_dkbar = (tp - tm) / (2.0 * hk);
    Eigen::Matrix<double, dim, dim> dk;  // dkappa / d arg_ij in the plane
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j) {
        const double h = kStep * std::max(1.0, std::abs(arg(i, j)));
        Mat3 a = arg;
        a(i, j) += h;
        update(a, kp, tp);
        a(i, j) -= 2.0 * h;
        update(a, km, tm);
        dk(i, j) = (kp - km) / (2.0 * h);
      }
    if (!fbar) {  // g_kj = sum_b du_bk dN_bj
      for (int b = 0; b < s.count; ++b)
        for (int k = 0; k < dim; ++k) d.dkappa_du[b][k] = dk.row(k).dot(s.dN[b]);
      return d;
    }
    // dFbar = alpha dF, alpha = (dJbar / dJ)^(1/dim): d alpha / alpha = (d dJbar / dJbar - d dJ / dJ) / dim,
    // d dJ / dJ = sum_b G_b . du_b (G = grad_x N at dF).
    const double alpha = std::pow(step_.fbar_dJbar()[p] / step_.fbar_dJ()[p], 1.0 / dim);
    double dk_dF = 0.0;
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j) dk_dF += dk(i, j) * dF(i, j);
    d.cell = dk_dF * alpha / dim;
    const auto& G = step_.gradients(p);
    for (int b = 0; b < s.count; ++b)
      for (int k = 0; k < dim; ++k) d.dkappa_du[b][k] = alpha * dk.row(k).dot(s.dN[b]) - d.cell * G[b][k];
    return d;
  }

  /// F-bar: each cell's coupling of its plastic points' kappa rows to the cell's volume
  /// change, -omega R_c V_c^T with R_c(a) = sum_{p in c} V_p N_a cell_p and V_c(b k) =
  /// sum_{q in c} beta_q G_qb,k, beta_q = w_q dJ_q / dJbar (the load step's F-bar V_c).
  void add_cell_terms() {
    const FBarCells<dim>& cells = *step_.fbar_cells();
    const auto& st = step_.stencils();
    const auto& pts = model_.points;
    double* values = tangent_.valuePtr();
    for (std::size_t c = 0; c < cells.members().size(); ++c) {
      const auto& members = cells.members()[c];
      if (std::none_of(members.begin(), members.end(), [&](int q) { return plastic_[q] >= 0; })) continue;
      const auto& nodes = cells.nodes()[c];
      const int nn = static_cast<int>(nodes.size());
      const auto at = [&](int node) {
        return static_cast<int>(std::lower_bound(nodes.begin(), nodes.end(), node) - nodes.begin());
      };
      Eigen::VectorXd R = Eigen::VectorXd::Zero(nn), U = Eigen::VectorXd::Zero(nn * dim);
      for (const int q : members) {
        const Stencil<dim>& s = st[q];
        const auto& G = step_.gradients(q);
        const double beta = cells.weight(q) * step_.fbar_dJ()[q] / step_.fbar_dJbar()[q];
        for (int a = 0; a < s.count; ++a) {
          const int k = at(s.node[a]);
          for (int i = 0; i < dim; ++i) U[k * dim + i] += beta * G[a][i];
          if (plastic_[q] >= 0 && kept(q, a)) R[k] += omega_ * pts.volume[q] * s.N[a] * sens_[plastic_[q]].cell;
        }
      }
      for (int a = 0; a < nn; ++a) {
        if (R[a] == 0.0) continue;
        const int row = dofs_.dof(nodes[a], dim);
        for (int b = 0; b < nn; ++b)
          for (int k = 0; k < dim; ++k) values[pattern_offset(tangent_, row, dofs_.dof(nodes[b], k))] -= R[a] * U[b * dim + k];
      }
    }
  }

  /// The central differences' step, relative to the argument (at least 1).
  static constexpr double kStep = 1e-7;

  LoadStep<dim>& step_;
  Model<dim>& model_;
  const NonlocalPlasticStrain<dim>& nonlocal_;
  DofMap dofs_;                   ///< nc per node, the active nodes numbered as the solid's
  Assembler<dim, nc> assembler_;  ///< over dofs_
  RowHalo halo_;                  ///< serial
  double l2_;
  double omega_ = 1.0;  ///< the nonlocal rows' scale E / h
  SparseMatrix tangent_;
  std::vector<double> helmholtz_;    ///< helmholtz_block()'s values in tangent_'s pattern
  std::vector<std::uint32_t> kept_;  ///< per point: the stencil entries of its regularised stencil
  Vector kbar0_;                     ///< kappa_bar_0 at the active nodes
  std::vector<bool> held_;           ///< active nodes in the Helmholtz system
  std::vector<int> constrained_;
  std::vector<double> increments_;
  // At the last residual()'s iterate:
  Vector du_, dk_;
  std::vector<double> kbar_;
  std::vector<Vec<dim>> grad_kbar_;
  // At the last tangent()'s:
  std::vector<int> plastic_;  ///< per point: its entry in sens_, -1 if not plastic
  std::vector<Sensitivity> sens_;
};

}  // namespace gradmpm::detail
