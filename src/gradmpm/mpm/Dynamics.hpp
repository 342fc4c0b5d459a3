#pragma once
// One time step of implicit MPM dynamics: the load step's quasi-static problem
// (mpm/LoadStep.hpp) with the points' inertia added, as geomechanics/mpm's Newmark scheme
// and Kratos' MPM do (Guilkey & Weiss 2003; Charlton, Coombs & Augarde 2017). Internal
// to the driver (mpm/QuasiStatic.hpp).
//
// At the start of the step the points' mass, momentum and mass-weighted acceleration go
// to the grid (the grid is fresh every step):
//   m_i = sum_p N_ip m_p,  M v_n = sum_p N_ip m_p v_p,  M a_n = sum_p N_ip m_p a_p
// with M lumped (diag m_i) or consistent (M_ij = sum_p N_ip N_jp m_p). The unknown is the
// grid displacement du of the step, and Newmark's relations give
//   a_n+1 = (du - dt v_n - dt^2 (1/2 - beta) a_n) / (beta dt^2)
//   v_n+1 = v_n + dt ((1 - gamma) a_n + gamma a_n+1)
// Generalised-alpha (Chung & Hulbert 1993) balances the forces at intermediate instants,
// the internal and external forces interpolated between t_n and t_n+1:
//   R = (1 - af) (f_ext - f_int)(du) + af (f_ext - f_int)_n
//       - M ((1 - am) a_n+1 + am a_n) - alpha M ((1 - af) v_n+1 + af v_n)
// (Newmark: am = af = 0), and the tangent -dR/ddu is
//   (1 - af) K + ((1 - am) / (beta dt^2) + alpha (1 - af) gamma / (beta dt)) M.
// After convergence the points take the grid's new acceleration and are advanced by
// Newmark's velocity update, a_p = sum_i N_ip a_i,n+1, v_p += dt ((1 - gamma) a_p,n +
// gamma a_p,n+1), as their positions are by the displacement (eq. 2); with
// TimeSettings::pic_fraction theta, v_p = (1 - theta) (that) + theta sum_i N_ip v_i,n+1. In the limit of
// points that do not move, with the consistent mass, this is the finite element method's
// Newmark exactly: v_p interpolates the grid's v, which the projection gives back.
//
// The first step of a run (t = 0) starts from the acceleration that balances the forces
// at t = 0, M a_0 = f_ext(0) - f_int(0): a body released under gravity falls as
// x0 + g t^2 / 2 from the first step. Constrained components move at the rate of their
// prescribed increment (v = du_c / dt, a = 0), fixed ones not at all.
#include <fmt/format.h>

#include <cmath>
#include <memory>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/mpm/LoadStep.hpp"
#include "gradmpm/solver/Dirichlet.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm::detail {

template <int dim>
class DynamicStep final : public NonlinearProblem {
 public:
  /// `step`: the step's quasi-static problem (stencils at x_n); `lambda_n`, `lambda_end`:
  /// the load factors at t_n and t_n+1; `initial`: t_n = 0 of a fresh run (the points'
  /// acceleration is then the one in balance at t = 0).
  DynamicStep(LoadStep<dim>& step, const Model<dim>& model, double dt, double lambda_n, double lambda_end,
              bool initial, const LinearSolverSettings& linear)
      : step_(step), time_(model.time), dt_(dt) {
    const auto [am, af, beta, gamma] = time_.coefficients();
    am_ = am, af_ = af, beta_ = beta, gamma_ = gamma;
    const DofMap& dofs = step.dofs();
    const int n = dofs.num_dofs();
    const bool split = ranks::distributed();
    if (time_.consistent_mass && split)
      throw UserError("[time] mass = \"consistent\" runs on one rank only; use mass = \"lumped\" on several");
    // The points' mass, momentum and mass-weighted acceleration at the nodes.
    Vector momentum = Vector::Zero(n), weighted = Vector::Zero(n);
    mass_share_ = Vector::Zero(n);
    const auto& st = step.stencils();
    const auto& pts = model.points;
    for (std::size_t p = 0; p < st.size(); ++p)
      for (int a = 0; a < st[p].count; ++a) {
        const double w = st[p].N[a] * pts.mass[p];
        for (int i = 0; i < dim; ++i) {
          const int r = dofs.dof(st[p].node[a], i);
          mass_share_[r] += w;
          momentum[r] += w * pts.velocity[p][i];
          weighted[r] += w * pts.acceleration[p][i];
        }
      }
    mass_ = mass_share_;
    for (Vector* v : {&mass_, &momentum, &weighted}) step.halo().sum(*v);
    if (time_.consistent_mass) {
      consistent_ = step.consistent_mass();
      mass_solver_ = make_linear_solver(linear, MatrixKind::Symmetric);
    }
    v_n_ = project(momentum);
    a_n_ = project(weighted);
    // Constrained components: at the rate of their prescribed increment.
    const auto& constrained = step.constrained();
    for (std::size_t k = 0; k < constrained.size(); ++k) {
      v_n_[constrained[k]] = step.increments()[k] / dt;
      a_n_[constrained[k]] = 0.0;
    }
    if (initial || af_ > 0.0) {
      // (f_ext - f_int) at t_n on this step's grid: the residual at du = 0 has f_ext at
      // t_n+1, whose live part is lambda_end / lambda_n times its value at t_n.
      Vector r0;
      step.residual(Vector::Zero(n), r0);
      const double ratio = lambda_end > 0.0 ? lambda_n / lambda_end : 0.0;
      r0 -= (1.0 - ratio) * step.live_load();
      for (int c : constrained) r0[c] = 0.0;
      if (initial) {
        a_n_ = project(r0);
        for (int c : constrained) a_n_[c] = 0.0;
        initial_ = true;
      }
      if (af_ > 0.0) balance_n_ = std::move(r0);
    }
  }

  const DofMap& dofs() const override { return step_.dofs(); }
  const RowHalo& halo() const override { return step_.halo(); }
  Eigen::MatrixXd node_coordinates() const override { return step_.node_coordinates(); }
  const std::vector<int>& constrained() const override { return step_.constrained(); }
  const std::vector<double>& increments() const override { return step_.increments(); }
  double largest_increment() const override { return step_.largest_increment(); }
  const SparseMatrix& pattern() const override { return step_.pattern(); }
  bool symmetric_tangent() const override { return step_.symmetric_tangent(); }
  double roundoff_force() const override { return step_.roundoff_force(); }

  ResidualNorms residual(const Vector& du, Vector& r) override {
    const ResidualNorms quasi_static = step_.residual(du, r);
    if (af_ > 0.0) r = (1.0 - af_) * r + af_ * balance_n_;
    const Vector a = acceleration(du);
    const Vector v = velocity(a);
    inertia_ = apply_mass((1.0 - am_) * a + am_ * a_n_);
    if (time_.damping > 0.0) inertia_ += time_.damping * apply_mass((1.0 - af_) * v + af_ * v_n_);
    r -= inertia_;
    for (int c : step_.constrained()) r[c] = 0.0;
    const auto [r_norm, inertia_norm] = step_.halo().template norms<2>({&r, &inertia_});
    return {r_norm, std::max(quasi_static.scale, inertia_norm)};
  }

  SparseMatrix& tangent(bool share) override {
    SparseMatrix& K = step_.tangent(share);
    double* values = K.valuePtr();
    const long nnz = static_cast<long>(K.nonZeros());
    if (af_ > 0.0)
      for (long k = 0; k < nnz; ++k) values[k] *= 1.0 - af_;
    const double c = (1.0 - am_) / (beta_ * dt_ * dt_) + time_.damping * (1.0 - af_) * gamma_ / (beta_ * dt_);
    if (time_.consistent_mass) {
      const double* m = consistent_.valuePtr();
      for (long k = 0; k < nnz; ++k) values[k] += c * m[k];
    } else {
      const Vector& m = share ? mass_share_ : mass_;
      for (Eigen::Index i = 0; i < m.size(); ++i)
        if (m[i] != 0.0) diagonal(K, static_cast<int>(i)) += c * m[i];
    }
    return K;
  }

  /// Reactions of the constrained components with the inertia and damping forces.
  void converged() override {
    step_.converged();
    step_.add_to_reactions(inertia_);
    const auto [inertia, f_ext, f_int] = step_.halo().template norms<3>({&inertia_, &step_.f_ext(), &step_.f_int()});
    const double scale = std::max(f_ext, f_int);
    inertia_ratio_ = scale > 0.0 ? inertia / scale : 0.0;
  }
  /// |M a + C v| against the larger of |f_ext| and |f_int| at the solution: how far from
  /// static balance the step ended (TimeSettings::stop_at_rest).
  double inertia_ratio() const { return inertia_ratio_; }

  /// After LoadStep::commit: the points' acceleration and velocity from the converged du.
  /// (At t = 0 the points' acceleration is first the one in balance, a_p,0 = sum_i N_ip a_i,0.)
  void commit(Model<dim>& model, const Vector& du) const {
    const Vector a = acceleration(du), v = velocity(a);
    const double pic = time_.pic_fraction;
    auto& pts = model.points;
    const int np = pts.size();
#pragma omp parallel for schedule(static) if (use_threads(np))
    for (int p = 0; p < np; ++p) {
      const Vec<dim> ap = interpolate(p, a);
      if (initial_) pts.acceleration[p] = interpolate(p, a_n_);
      const Vec<dim> newmark = pts.velocity[p] + dt_ * ((1.0 - gamma_) * pts.acceleration[p] + gamma_ * ap);
      pts.velocity[p] = pic > 0.0 ? Vec<dim>((1.0 - pic) * newmark + pic * interpolate(p, v)) : newmark;
      pts.acceleration[p] = ap;
    }
  }

 private:
  /// sum_i N_ip x_i at point p.
  Vec<dim> interpolate(int p, const Vector& x) const {
    const auto& s = step_.stencils()[p];
    const DofMap& dofs = step_.dofs();
    Vec<dim> y = Vec<dim>::Zero();
    for (int k = 0; k < s.count; ++k)
      for (int i = 0; i < dim; ++i) y[i] += s.N[k] * x[dofs.dof(s.node[k], i)];
    return y;
  }

  /// a_n+1 of the iterate du (Newmark).
  Vector acceleration(const Vector& du) const {
    return (du - dt_ * v_n_ - dt_ * dt_ * (0.5 - beta_) * a_n_) / (beta_ * dt_ * dt_);
  }
  Vector velocity(const Vector& a) const { return v_n_ + dt_ * ((1.0 - gamma_) * a_n_ + gamma_ * a); }

  /// M x (a distributed run's lumped M: right in own and ghost rows).
  Vector apply_mass(const Vector& x) const {
    if (time_.consistent_mass) return consistent_ * x;
    return mass_.cwiseProduct(x);
  }

  /// The nodal values y with M y = b (b: mass-weighted sums of the points' values). Lumped:
  /// y = b / m (0 at a node without mass). Consistent: a solve with M, which a node that
  /// only a few points reach makes singular.
  Vector project(const Vector& b) {
    if (!time_.consistent_mass) {
      Vector y = Vector::Zero(b.size());
      for (Eigen::Index i = 0; i < b.size(); ++i)
        if (mass_[i] > 0.0) y[i] = b[i] / mass_[i];
      return y;
    }
    try {
      if (!mass_factorised_) {
        mass_solver_->describe({dim, [this] { return step_.node_coordinates(); }, false, nullptr});
        mass_solver_->analyze(consistent_);
        mass_solver_->factorize(consistent_);
        mass_factorised_ = true;
      }
      return mass_solver_->solve(b);
    } catch (const SolverError& e) {
      throw StepFailure{fmt::format(
          "the consistent mass matrix cannot be factorised ({}): cells with fewer points than nodes make it "
          "singular; use [time] mass = \"lumped\"",
          e.what())};
    }
  }

  /// K's diagonal entry of row i (the pattern holds every active dof's).
  static double& diagonal(SparseMatrix& K, int i) {
    const int* outer = K.outerIndexPtr();
    const int* inner = K.innerIndexPtr();
    const int* at = std::lower_bound(inner + outer[i], inner + outer[i + 1], i);
    if (at == inner + outer[i + 1] || *at != i) throw std::logic_error("the tangent's pattern lacks a diagonal entry");
    return K.valuePtr()[at - inner];
  }

  LoadStep<dim>& step_;
  const TimeSettings& time_;
  double dt_;
  double am_ = 0.0, af_ = 0.0, beta_ = 0.25, gamma_ = 0.5;
  Vector mass_, mass_share_;  ///< lumped: summed over the ranks, and this rank's points' own
  SparseMatrix consistent_;   ///< consistent mass (serial runs)
  std::unique_ptr<LinearSolver> mass_solver_;
  bool mass_factorised_ = false;
  bool initial_ = false;  ///< t_n = 0 of a fresh run: a_n is the acceleration in balance
  Vector v_n_, a_n_;   ///< the grid's velocity and acceleration at t_n
  Vector balance_n_;   ///< generalised-alpha: (f_ext - f_int) at t_n
  Vector inertia_;     ///< M a + C v at the last residual()'s iterate
  double inertia_ratio_ = 0.0;
};

}  // namespace gradmpm::detail
