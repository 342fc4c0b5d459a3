#pragma once
// One step of the coupled displacement-pressure (u-p) MPM of a saturated soil: the load
// step's solid (mpm/LoadStep.hpp) with the pore pressure p on the same grid and basis,
// solved monolithically (Biot's mixture in one-point form: Terzaghi's effective stress,
// Darcy's flow; Zienkiewicz et al. 1999, ch. 3; docs/pore-pressure.md). Internal to the
// driver (mpm/QuasiStatic.cpp).
//
// Unknowns per active node: the step's displacement du (dim) and pore-pressure increment
// dp. Points carry p (MaterialPoints::pore_pressure); at the start of the step it goes to
// the nodes by the L2 projection M p_n = sum_p N_ap V_p p_p (nodal_pressure()), and after
// the step the points take p_p += sum_a N_ap dp_a. The equations, with P_p = p_p + sum_a N_ap dp_a:
//   momentum:  f_ext - f_int(sigma') + sum_p P_p v_p grad_x N_a = 0             (total stress sigma' - p I)
//   mass:      sum_p [N_a (dv_p + S_p V_p dP_p) + dt (k / gamma_w) V_p grad N_a . (grad p_n+1 - rho_w g)]
//              + tau / (2 G) sum_p V_p (N_a - Nbar_a)(dP_p - dPbar) = 0
// dv_p = V_p (det dF - 1) the point's volume change (finite strain; V_p tr(g) small), v_p =
// V_p det dF its volume at the step's end, S_p = n_p / K_f the fluid's storage (incompressible
// grains), the flow by backward Euler in the configuration at the step's start (the
// stencils' x_n, as the point loop's), and the last term the polynomial pressure projection
// (Dohrmann & Bochev 2004; White & Borja 2008): Nbar, dPbar the means over the points that
// share a stencil (a cell's, for the linear basis). The mass rows are scaled by omega = E /
// h (forces per volume change), so that Newton's residual weighs both fields alike. The
// tangent is [K + K_p, -Q; omega Q^T, omega (S + dt H + T)], Q_(ai)b = sum_p v_p grad N_ai N_b,
// K_p the geometric term of p on the current volume (finite strain).
//
// With F-bar the volume change is the cell's, shared by its points as F-bar shares it
// (mpm/FBar.hpp): the mass balance sees each point's dv through the cell's mean shape
// function Nbar_a,c = sum_{p in c} V_p N_ap / V_c, and the momentum balance, its adjoint, the
// cell's mean pressure Pbar_c = sum_{p in c} V_p P_p / V_c on each point's v grad_x N. Without
// it the pore pressure constrains each point's own volume change, and that locked: a smooth
// footing on undrained von Mises clay carried 5.74 c at s/B = 0.045 (5.20 c in total stress
// with nu = 0.499 and F-bar).
#include <fmt/format.h>

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/mpm/LoadStep.hpp"
#include "gradmpm/mpm/NodeBlocks.hpp"

namespace gradmpm::detail {

template <int dim>
class ConsolidationStep final : public NonlinearProblem {
 public:
  static constexpr int nc = dim + 1;  ///< components per node: du and dp

  /// `dt`: the step's time increment (the flow's; 0 without flow); `lambda_end`: the load
  /// factor at the step's end (the fluid's weight in Darcy's law follows it).
  ConsolidationStep(LoadStep<dim>& step, const Model<dim>& model, double dt, double lambda_end)
      : step_(step),
        model_(model),
        dofs_(step.stencils(), model.grid.num_nodes(), nc),
        assembler_(step.stencils(), model.points, dofs_, &model.grid),
        dt_(model.pore.flows() ? dt : 0.0),
        lambda_(lambda_end) {
    if (ranks::distributed()) throw std::logic_error("the coupled u-p step runs on one rank");
    omega_ = stiffest_young(model.materials) / model.grid.cell_size().minCoeff();
    tangent_ = grown_pattern<dim, nc>(step.pattern(), step.dofs().num_active_nodes());
    if (const FBarCells<dim>* cells = step.fbar_cells()) cell_means(*cells);
    nodal_pressure();
    point_coefficients();
    projection_groups();
    constraints();
  }

  const DofMap& dofs() const override { return dofs_; }
  const RowHalo& halo() const override { return halo_; }
  Eigen::MatrixXd node_coordinates() const override { return dofs_.coordinates(model_.grid); }
  const std::vector<int>& constrained() const override { return constrained_; }
  const std::vector<double>& increments() const override { return increments_; }
  double largest_increment() const override { return largest_increment_; }
  const SparseMatrix& pattern() const override { return tangent_; }
  bool symmetric_tangent() const override { return false; }
  double roundoff_force() const override { return step_.roundoff_force(); }

  ResidualNorms residual(const Vector& x, Vector& r) override {
    split(x);
    Vector r_u;
    const ResidualNorms solid = step_.residual(du_, r_u);
    point_values();
    // The pore pressure's force sum_p P_p v_p grad_x N_a, and the mass balance.
    f_p_ = Vector::Zero(step_.dofs().num_dofs());
    r = Vector::Zero(dofs_.num_dofs());
    const DofMap& u_dofs = step_.dofs();
    const auto& st = step_.stencils();
    const bool cells = !cell_nodes_.empty();
    // The flow's two terms in balance at rest (the pressure gradient's, the fluid weight's):
    // their sizes join the residual's scale, as f_ext and f_int do.
    Vector gradient_flow = Vector::Zero(dofs_.num_active_nodes()), weight_flow = gradient_flow;
    assembler_.for_each_point_disjoint([&](int p) {
      const Stencil<dim>& s = st[p];
      const auto& G = step_.gradients(p);
      const double force = pressure_on(p) * volume_[p];
      const double dPbar = group_dP_[group_[p]];
      const double dv = cells ? 0.0 : dv_[p];  // (F-bar: the cell's, below)
      for (int a = 0; a < s.count; ++a) {
        for (int i = 0; i < dim; ++i) f_p_[u_dofs.dof(s.node[a], i)] += force * G[a][i];
        double flow = 0.0, weight = 0.0;
        for (int j = 0; j < dim; ++j) {
          flow += s.dN[a][j] * flux_[p][j];
          weight += s.dN[a][j] * weight_[p][j];
        }
        const int e = dofs_.dof(s.node[a], 0) / nc;
        gradient_flow[e] += omega_ * mobility_[p] * (flow + weight);
        weight_flow[e] += omega_ * mobility_[p] * weight;
        const double mass = s.N[a] * (dv + storage_[p] * (P_[p] - model_.points.pore_pressure[p])) +
                            mobility_[p] * flow +
                            stab_[p] * (s.N[a] * (P_[p] - model_.points.pore_pressure[p]) -
                                        group_N_[group_[p]][a] * dPbar);
        r[dofs_.dof(s.node[a], dim)] -= omega_ * mass;
      }
    });
    for (std::size_t c = 0; c < cell_nodes_.size(); ++c) {  // F-bar: sum_c Nbar_a,c dv_c
      double dv = 0.0;
      for (const int q : step_.fbar_cells()->members()[c]) dv += dv_[q];
      for (std::size_t k = 0; k < cell_nodes_[c].size(); ++k)
        r[dofs_.dof(cell_nodes_[c][k], dim)] -= omega_ * cell_N_[c][k] * dv;
    }
    for (int e = 0; e < u_dofs.num_active_nodes(); ++e)
      for (int i = 0; i < dim; ++i) r[e * nc + i] = r_u[e * dim + i] + f_p_[e * dim + i];
    for (int c : constrained_) r[c] = 0.0;
    const Vector f_total = step_.f_int() - f_p_;
    const double total = f_total.norm();
    const double flows = std::max(gradient_flow.norm(), weight_flow.norm());
    const double scale = std::isfinite(total) ? std::max({solid.scale, total, flows}) : solid.scale;
    return {r.norm(), scale};
  }

  SparseMatrix& tangent(bool /*share*/) override {
    const SparseMatrix& K = step_.tangent(false);
    std::fill(tangent_.valuePtr(), tangent_.valuePtr() + tangent_.nonZeros(), 0.0);
    add_node_blocks<dim, nc>(K, tangent_);
    assembler_.add_matrix(tangent_, [&](int p, const Stencil<dim>& s, typename Assembler<dim, nc>::LocalMatrix& Ke) {
      const auto& G = step_.gradients(p);
      const bool finite = model_.material_of(p).finite_strain();
      const double v = volume_[p], V = model_.points.volume[p], P = pressure_on(p);
      const auto& Nbar = group_N_[group_[p]];
      const bool own = cell_nodes_.empty();  // (F-bar: Q through the cells, below)
      for (int b = 0; b < s.count; ++b)
        for (int a = 0; a < s.count; ++a) {
          if (finite)  // d(v grad_x N_ai)/du_bk = v (G_ai G_bk - G_ak G_bi)
            for (int i = 0; i < dim; ++i)
              for (int k = 0; k < dim; ++k) Ke(a * nc + i, b * nc + k) -= P * v * (G[a][i] * G[b][k] - G[a][k] * G[b][i]);
          if (own) {
            for (int i = 0; i < dim; ++i) Ke(a * nc + i, b * nc + dim) -= v * G[a][i] * s.N[b];
            for (int k = 0; k < dim; ++k)
              Ke(a * nc + dim, b * nc + k) += omega_ * s.N[a] * (finite ? v * G[b][k] : V * s.dN[b][k]);
          }
          double laplace = 0.0;
          for (int j = 0; j < dim; ++j) laplace += s.dN[a][j] * s.dN[b][j];
          Ke(a * nc + dim, b * nc + dim) +=
              omega_ * (storage_[p] * s.N[a] * s.N[b] + mobility_[p] * laplace +
                        stab_[p] * (s.N[a] * s.N[b] - Nbar[a] * Nbar[b]));
        }
    });
    if (!cell_nodes_.empty()) add_cell_coupling();
    return tangent_;
  }

  /// The reactions of the constrained displacements with the pore pressure's force.
  void converged() override {
    step_.converged();
    step_.add_to_reactions(-f_p_);
  }

  /// p_n + dp at every grid node (zero on inactive nodes) for the converged x.
  Vector grid_pressure(const Vector& x) const {
    Vector p = p_n_;
    for (int e = 0; e < dofs_.num_active_nodes(); ++e) p[e] += x[e * nc + dim];
    Vector g = Vector::Zero(model_.grid.num_nodes());
    for (int e = 0; e < dofs_.num_active_nodes(); ++e) g[dofs_.node_of(e)] = p[e];
    return g;
  }

  /// After convergence: the points' pore pressure; returns the displacement part of x (for
  /// LoadStep::commit).
  Vector commit(Model<dim>& model, const Vector& x) {
    split(x);
    point_values();
    for (int p = 0; p < model.points.size(); ++p) model.points.pore_pressure[p] = P_[p];
    return du_;
  }

 private:
  /// The pressure point p's volume carries: its own, or with F-bar its cell's mean (from
  /// point_values()).
  double pressure_on(int p) const { return cell_nodes_.empty() ? P_[p] : cell_P_[step_.fbar_cells()->cell(p)]; }

  /// F-bar: each cell's nodes (those of its points' stencils), its points' volume and the
  /// mean of their shape functions Nbar_a,c.
  void cell_means(const FBarCells<dim>& cells) {
    const auto& st = step_.stencils();
    const auto& pts = model_.points;
    cell_nodes_ = cells.nodes();
    cell_N_.resize(cell_nodes_.size());
    cell_volume_.assign(cell_nodes_.size(), 0.0);
    for (std::size_t c = 0; c < cell_nodes_.size(); ++c) {
      const auto& nodes = cell_nodes_[c];
      cell_N_[c].assign(nodes.size(), 0.0);
      for (const int q : cells.members()[c]) {
        cell_volume_[c] += pts.volume[q];
        for (int a = 0; a < st[q].count; ++a)
          cell_N_[c][std::lower_bound(nodes.begin(), nodes.end(), st[q].node[a]) - nodes.begin()] +=
              pts.volume[q] * st[q].N[a];
      }
      for (double& n : cell_N_[c]) n /= cell_volume_[c];
    }
  }

  /// F-bar: the cells' rank-one couplings of du and dp, -U_c Nbar_c^T and omega Nbar_c U_c^T,
  /// U_c(a i) = sum_{q in c} v_q grad_x N_qa,i (v_q and grad_x N actual: dv_c's derivative).
  void add_cell_coupling() {
    const auto& st = step_.stencils();
    double* values = tangent_.valuePtr();
    for (std::size_t c = 0; c < cell_nodes_.size(); ++c) {
      const auto& nodes = cell_nodes_[c];
      const int nn = static_cast<int>(nodes.size());
      Eigen::VectorXd U = Eigen::VectorXd::Zero(nn * dim);
      for (const int q : step_.fbar_cells()->members()[c]) {
        const auto& G = step_.gradients(q);
        for (int a = 0; a < st[q].count; ++a) {
          const int at = static_cast<int>(std::lower_bound(nodes.begin(), nodes.end(), st[q].node[a]) - nodes.begin());
          for (int i = 0; i < dim; ++i) U[at * dim + i] += volume_[q] * G[a][i];
        }
      }
      for (int b = 0; b < nn; ++b) {
        const int p_col = dofs_.dof(nodes[b], dim);
        for (int a = 0; a < nn; ++a) {
          for (int i = 0; i < dim; ++i) {
            values[pattern_offset(tangent_, dofs_.dof(nodes[a], i), p_col)] -= U[a * dim + i] * cell_N_[c][b];
            values[pattern_offset(tangent_, dofs_.dof(nodes[b], dim), dofs_.dof(nodes[a], i))] +=
                omega_ * cell_N_[c][b] * U[a * dim + i];
          }
        }
      }
    }
  }

  /// p_n at the nodes: the L2 projection of the points' p, M p_n = sum_p N_a V_p p_p with
  /// M_ab = sum_p N_a N_b V_p. A point field that interpolates nodal values (what the last
  /// step left) comes back exactly: a drained node keeps the value it is held at. (The
  /// lumped projection, p_n,a = sum_p N_a V_p p_p / sum_p N_a V_p, does not: the points
  /// beside a drained face drifted each step until their mean, not their interpolant, was
  /// 0, and the isochrone's error was 3 % of p_0 at the face in Terzaghi's problem.) Where
  /// M is singular (a cell with fewer points than nodes), the lumped projection.
  void nodal_pressure() {
    const auto& st = step_.stencils();
    const auto& pts = model_.points;
    const int nodes = dofs_.num_active_nodes();
    Vector lumped = Vector::Zero(nodes), b = Vector::Zero(nodes);
    for (std::size_t p = 0; p < st.size(); ++p)
      for (int a = 0; a < st[p].count; ++a) {
        const int e = dofs_.dof(st[p].node[a], 0) / nc;
        lumped[e] += st[p].N[a] * pts.volume[p];
        b[e] += st[p].N[a] * pts.volume[p] * pts.pore_pressure[p];
      }
    p_n_ = Vector::Zero(nodes);
    if (b.lpNorm<Eigen::Infinity>() == 0.0) return;  // (no pore pressure yet)
    const DofMap scalar(st, model_.grid.num_nodes(), 1);
    SparseMatrix M = build_pattern(st, scalar);
    Assembler<dim>(st, pts, scalar).add_mass(M);
    const Eigen::SimplicialLDLT<SparseMatrix> ldlt(M);
    if (ldlt.info() == Eigen::Success && (ldlt.vectorD().array() > 1e-12 * lumped.maxCoeff()).all()) {
      p_n_ = ldlt.solve(b);
      return;
    }
    for (int e = 0; e < nodes; ++e)
      if (lumped[e] > 0.0) p_n_[e] = b[e] / lumped[e];
  }

  /// Each point's storage S V, mobility dt k(n) / gamma_w V (n at the step's start),
  /// projection weight tau V / (2 G),
  /// and the fluid's weight rho_w g (at the step's load factor; in full where gravity is a dead load).
  void point_coefficients() {
    const auto& pts = model_.points;
    const int np = pts.size();
    storage_.resize(np);
    mobility_.resize(np);
    stab_.resize(np);
    weight_.resize(np);
    for (int p = 0; p < np; ++p) {
      const PoreFluid& f = model_.pore.fluids[pts.material[p]];
      const double J = pts.F[p].determinant();
      const double n = std::clamp(1.0 - (1.0 - f.porosity) / J, 0.0, 1.0);
      const double V = pts.volume[p];
      storage_[p] = n / f.bulk_modulus * V;
      const double gamma_w = f.density * model_.pore.gravity;
      mobility_[p] = gamma_w > 0.0 ? dt_ * f.conductivity_at(n) / gamma_w * V : 0.0;
      const IsotropicElasticity& el = model_.material_of(p).elasticity();
      const double shear = el.young / (2.0 * (1.0 + el.poisson));
      stab_[p] = model_.pore.stabilisation * V / (2.0 * shear);
      weight_[p] = f.density * (model_.dead_gravity ? 1.0 : lambda_) * model_.gravity;
    }
  }

  /// The pressure projection's groups: the points with the same stencil nodes (one run
  /// of the assembler: a cell's points, for the linear basis), and their mean N.
  void projection_groups() {
    const auto& st = step_.stencils();
    const int np = static_cast<int>(st.size());
    std::vector<int> order(np);
    std::iota(order.begin(), order.end(), 0);
    const auto less = [&](int p, int q) {
      if (st[p].count != st[q].count) return st[p].count < st[q].count;
      return std::lexicographical_compare(st[p].node.begin(), st[p].node.begin() + st[p].count, st[q].node.begin(),
                                          st[q].node.begin() + st[q].count);
    };
    std::sort(order.begin(), order.end(), less);
    group_.assign(np, 0);
    group_N_.clear();
    group_weight_.clear();
    for (int k = 0; k < np; ++k) {
      const int p = order[k];
      if (k == 0 || less(order[k - 1], p)) {
        group_N_.emplace_back();
        group_N_.back().fill(0.0);
        group_weight_.push_back(0.0);
      }
      const int g = static_cast<int>(group_N_.size()) - 1;
      group_[p] = g;
      group_weight_[g] += stab_[p];
      for (int a = 0; a < st[p].count; ++a) group_N_[g][a] += stab_[p] * st[p].N[a];
    }
    for (std::size_t g = 0; g < group_N_.size(); ++g)
      if (group_weight_[g] > 0.0)
        for (auto& v : group_N_[g]) v /= group_weight_[g];
    group_dP_.assign(group_N_.size(), 0.0);
  }

  /// The solid's constraints in the combined numbering, and the pressure constraints (the
  /// increment that takes the node's p_n to the value held).
  void constraints() {
    std::vector<std::pair<int, double>> held_p;  // (equation, increment) of the pressures held
    largest_increment_ = step_.largest_increment();
    std::vector<int> held;  // the blocks holding an active node
    for (const PressureConstraint& pc : model_.pore.constraints) {
      if (!dofs_.active(pc.node)) continue;
      held.push_back(pc.block);
      const int e = dofs_.dof(pc.node, 0) / nc;
      const double inc = pc.value - p_n_[e];
      held_p.push_back({e * nc + dim, inc});
      largest_increment_ = std::max(largest_increment_, std::abs(inc));
    }
    // A drained face on the grid's boundary drains only while points reach it: a body
    // that settles away from it would go on undrained without a word.
    for (const PressureConstraint& pc : model_.pore.constraints)
      if (std::find(held.begin(), held.end(), pc.block) == held.end())
        throw SolverError(fmt::format(
            "pressure_constraints[{}] holds no node a point reaches any more: the body has moved off it and would "
            "no longer drain; give the drained boundary as a band (min, max) that the body's surface stays in",
            pc.block));
    node_block_constraints<dim>(step_.constrained(), step_.increments(), std::move(held_p), constrained_, increments_);
  }

  /// du (the solid's numbering) and dp (per active node) of the combined x.
  void split(const Vector& x) { split_node_blocks<dim>(x, du_, dp_); }

  /// At the points: P = p_n + sum N dp, the volume v at the step's end, the volume change,
  /// grad p_n+1 - rho_w g (Darcy's flux is -k / gamma_w times it), and each group's mean dP.
  void point_values() {
    const auto& st = step_.stencils();
    const auto& pts = model_.points;
    const int np = pts.size();
    P_.resize(np);
    volume_.resize(np);
    dv_.resize(np);
    flux_.resize(np);
    const DofMap& u_dofs = step_.dofs();
    for (int p = 0; p < np; ++p) {
      const Stencil<dim>& s = st[p];
      double dP = 0.0;
      Vec<dim> grad = Vec<dim>::Zero();
      for (int a = 0; a < s.count; ++a) {
        const int e = dofs_.dof(s.node[a], 0) / nc;
        dP += s.N[a] * dp_[e];
        for (int j = 0; j < dim; ++j) grad[j] += s.dN[a][j] * (p_n_[e] + dp_[e]);
      }
      P_[p] = pts.pore_pressure[p] + dP;
      const Mat3 g = increment_gradient(s, u_dofs, du_);
      const double V = pts.volume[p];
      if (model_.material_of(p).finite_strain()) {
        const double det = (Mat3::Identity() + g).determinant();
        volume_[p] = V * det;
        dv_[p] = V * (det - 1.0);
      } else {
        volume_[p] = V;
        dv_[p] = V * g.trace();
      }
      flux_[p] = grad - weight_[p];
    }
    if (const FBarCells<dim>* cells = step_.fbar_cells()) {  // each cell's volume-weighted mean P
      cell_P_.assign(cell_nodes_.size(), 0.0);
      for (std::size_t c = 0; c < cell_nodes_.size(); ++c) {
        for (const int q : cells->members()[c]) cell_P_[c] += P_[q] * pts.volume[q];
        cell_P_[c] /= cell_volume_[c];
      }
    }
    std::fill(group_dP_.begin(), group_dP_.end(), 0.0);
    for (int p = 0; p < np; ++p) group_dP_[group_[p]] += stab_[p] * (P_[p] - pts.pore_pressure[p]);
    for (std::size_t g = 0; g < group_dP_.size(); ++g)
      if (group_weight_[g] > 0.0) group_dP_[g] /= group_weight_[g];
  }

  LoadStep<dim>& step_;
  const Model<dim>& model_;
  DofMap dofs_;                   ///< nc per node, the active nodes numbered as the solid's
  Assembler<dim, nc> assembler_;  ///< over dofs_
  RowHalo halo_;                  ///< serial
  double dt_, lambda_;
  double omega_ = 1.0;  ///< the mass rows' scale E / h
  SparseMatrix tangent_;
  Vector p_n_;  ///< p_n at the active nodes
  std::vector<double> storage_, mobility_, stab_;
  std::vector<Vec<dim>> weight_;  ///< rho_w g at the step's load factor (in full: a dead gravity)
  std::vector<int> group_;        ///< each point's projection group
  std::vector<std::array<double, Stencil<dim>::capacity>> group_N_;  ///< its stab-weighted mean N
  std::vector<double> group_weight_, group_dP_;
  // F-bar (empty without): each cell's nodes, mean shape functions and volume.
  std::vector<std::vector<int>> cell_nodes_;
  std::vector<std::vector<double>> cell_N_;
  std::vector<double> cell_volume_;
  std::vector<int> constrained_;
  std::vector<double> increments_;
  double largest_increment_ = 0.0;
  // At the last residual()'s iterate:
  Vector du_, dp_;
  std::vector<double> P_, volume_, dv_;
  std::vector<double> cell_P_;  ///< F-bar: each cell's mean P
  std::vector<Vec<dim>> flux_;
  Vector f_p_;  ///< sum_p P_p v_p grad_x N_a (the solid's numbering)
};

}  // namespace gradmpm::detail
