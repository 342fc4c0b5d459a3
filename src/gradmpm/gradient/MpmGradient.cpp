#include "gradmpm/gradient/MpmGradient.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <memory>
#include <optional>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Parallel.hpp"
#include "gradmpm/core/SymmetricTensor.hpp"
#include "gradmpm/core/Timer.hpp"
#include "gradmpm/gradient/Helmholtz.hpp"
#include "gradmpm/points/Transfer.hpp"

namespace gradmpm {

namespace {

/// Everything the smoothing needs on the points' current configuration: stencils,
/// scalar equation numbering, pattern, assembler, and the factorised operators (one for
/// natural boundaries, one per distinct Dirichlet set of u-RA).
///
/// Its methods take and return fields at the model's points. A distributed run's model
/// holds this rank's points (mpm/RankPoints.hpp): the context makes their stencils, their
/// share of the Helmholtz systems (the solver adds the shares up) and the smoothed fields
/// at them.
template <int dim>
class SmoothingContext {
 public:
  /// `node_order`: the load step's elimination order of the grid nodes (StepInfo's
  /// DriverState::ordering.nodes; empty: none), which the first smoother's analysis compares
  /// with its own ordering (smoother()).
  SmoothingContext(const Model<dim>& m, double l, const LinearSolverSettings& backend,
                   const std::vector<int>& node_order = {})
      : model_(m),
        l_(l),
        backend_(backend),
        node_order_(node_order),
        split_(owned_points(m)),
        st_(stencils(m)),
        // (a distributed run: numbered by the nodes' owners; each rank knows its own and
        // its stencils' nodes, and the choices made from its held nodes below are made
        // over the ranks)
        dofs_(st_, m.grid.num_nodes(), 1, m.rank_boxes, 0),
        assembler_(st_, m.points, dofs_, &m.grid),
        pattern_(build_rank_pattern(st_, dofs_)) {}

  /// Natural-boundary smoothing of a symmetric tensor field at the points: the
  /// components that can be non-zero in `dim` (in-plane ones and the out-of-plane
  /// diagonal) are loaded in one pass over the points, solved in one sweep and
  /// interpolated back in one pass.
  /// On a roller (a symmetry plane, a frictionless support: some but not all components
  /// held) with normal d, a shear component (i, j) with i or j = d is odd across the plane:
  /// it is held at zero there, the other components keep the natural condition.
  std::vector<Mat3> smooth_tensor(const std::vector<Mat3>& t) {
    std::vector<std::array<int, 2>> comps;
    for (const auto& c : kSymmetricComponents)
      if (c.i == c.j || (c.i < dim && c.j < dim)) comps.push_back({c.i, c.j});
    const int nc = static_cast<int>(comps.size());
    if (!natural_) natural_ = smoother(l_, {});
    Eigen::MatrixXd F = assembler_.load_columns(nc, [&](int p, int j) { return t[p](comps[j][0], comps[j][1]); });
    Eigen::MatrixXd G = natural_->smooth_loads(F);
    for (int j = 0; j < nc; ++j) {
      const auto [zero, key] = odd_dofs(comps[j][0], comps[j][1]);
      if (!ranks::any(!zero.empty())) continue;  // (every rank's: making a smoother is collective)
      auto& sm = by_constraints_[key];
      if (!sm) sm = smoother(l_, zero);
      Eigen::MatrixXd f = F.col(j);
      for (int d : zero) f(d, 0) = 0.0;
      G.col(j) = sm->smooth_loads(f).col(0);
    }
    std::vector<Mat3> out(model_.points.size(), Mat3::Zero());
    assembler_.interpolate_columns(
        G, [&](int p, int j, double v) { out[p](comps[j][0], comps[j][1]) = out[p](comps[j][1], comps[j][0]) = v; });
    return out;
  }

  /// The equations of the roller nodes across which component (i, j) is odd (none for
  /// i = j): nodes of a roller block (some but not all components held) holding i or j,
  /// and held nodes of other blocks on the plane of such a roller (where a symmetry plane
  /// meets a fixed base). Elsewhere a fixed support (no slip) keeps the natural condition.
  /// Also returns the key of its smoother (held_dofs).
  std::pair<std::vector<int>, std::vector<int>> odd_dofs(int i, int j) const {
    if (i == j) return {};
    std::vector<int> nodes;
    const double tol = 1e-9 * model_.grid.cell_size().minCoeff();
    for (const auto& k : model_.constraints) {
      if (!k.gradient_boundary) continue;
      bool odd = k.roller && (k.component == i || k.component == j);
      for (const auto& [axis, at] : model_.roller_planes)
        odd = odd || ((axis == i || axis == j) && std::abs(model_.grid.node_position(k.node)[axis] - at) <= tol);
      if (odd) nodes.push_back(k.node);
    }
    return held_dofs(nodes);
  }

  /// The equations of `nodes` that this rank knows (serially: the active ones), ascending,
  /// and the key of the smoother that holds them: serially the equations themselves (the
  /// same held set shares one factorisation); in a distributed run the nodes (the same
  /// on every rank, so every rank makes a smoother, a collective call, at the same calls).
  std::pair<std::vector<int>, std::vector<int>> held_dofs(std::vector<int> nodes) const {
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    std::vector<int> dofs;
    for (const int n : nodes)
      if (dofs_.active(n)) dofs.push_back(dofs_.dof(n, 0));
    return {dofs, split_ ? nodes : dofs};
  }


  /// u-RA: smoothing of displacement component `comp`, held on the nodes where the
  /// classical problem holds that component (supports marked gradient_boundary = false,
  /// which only remove rigid motion, excepted). The held values are the classical field's
  /// own nodal values: with the grid reset after every step these are not stored, so
  /// they are the L2 projection of the point field, M u = sum_p N c_p V_p (exact for
  /// linear fields; the prescribed value itself in the FEM limit). Returns nodal values.
  Vector smooth_displacement(const std::vector<double>& c, int comp) {
    std::vector<int> nodes;
    for (const auto& k : model_.constraints)
      if (k.component == comp && k.gradient_boundary) nodes.push_back(k.node);
    const auto [dofs, key] = held_dofs(nodes);
    std::vector<double> values;
    if (ranks::any(!dofs.empty())) {  // (every rank's: the projection is collective)
      const Vector projected = project(c);
      for (int d : dofs) values.push_back(projected[d]);
    }
    auto& sm = by_constraints_[key];
    if (!sm) sm = smoother(l_, dofs);
    return sm->smooth_point_field(c, values);
  }

  /// The L2 projection of a point field onto the nodes, M u = sum_p N c_p V_p. The
  /// consistent mass matrix is singular when the points do not determine every nodal
  /// value (GIMP nodes whose support only touches the material, e.g. beyond a symmetry
  /// plane, or fewer points than nodes in a cell row): then the lumped projection,
  /// u_i = sum_p N_i c_p V_p / sum_p N_i V_p (the MPM's own mapping; 0 where no point weighs).
  Vector project(const std::vector<double>& c) {
    if (!projector_ && !lumped_) {
      try {
        projector_ = smoother(0.0, {});
      } catch (const SolverError&) {
        lumped_ = summed_load(std::vector<double>(c.size(), 1.0));
      }
    }
    if (projector_) return projector_->smooth_point_field(c);
    Vector u = summed_load(c);
    for (Eigen::Index i = 0; i < u.size(); ++i) u[i] = (*lumped_)[i] > 0.0 ? u[i] / (*lumped_)[i] : 0.0;
    return u;
  }

  /// sum_p N_i c_p V_p over every point (a distributed run: the ranks add their points',
  /// in this rank's own and ghost rows, between neighbours).
  Vector summed_load(const std::vector<double>& c) {
    Vector f = assembler_.load(c);
    if (split_) {
      if (!halo_) halo_.emplace(dofs_.rank_rows(), touched_rows(pattern_), dofs_.global_rows());
      halo_->sum(f);
    }
    return f;
  }

  /// Seconds the sparse solvers of this context have taken.
  double solver_seconds() const {
    double t = 0.0;
    for (const auto* sm : {natural_.get(), projector_.get()})
      if (sm) t += sm->solver_seconds();
    for (const auto& [dofs, sm] : by_constraints_) t += sm->solver_seconds();
    return t;
  }

  /// Point values and gradients (at the model's points) of a nodal scalar field.
  void interpolate(const Vector& nodal, std::vector<double>& value, std::vector<Vec<dim>>& gradient) const {
    value.assign(st_.size(), 0.0);
    gradient.assign(st_.size(), Vec<dim>::Zero());
    for (std::size_t p = 0; p < st_.size(); ++p)
      for (int a = 0; a < st_[p].count; ++a) {
        const double v = nodal[dofs_.dof(st_[p].node[a], 0)];
        value[p] += st_[p].N[a] * v;
        gradient[p] += st_[p].dN[a] * v;
      }
  }

 private:
  /// A smoother of this context's pattern. The first one made orders the pattern (AMD,
  /// METIS: most of an analysis, 3.6 s at 5e5 nodes in 2D); the others take its ordering,
  /// so that a step's smoothers, which differ only in their values (length scale, held
  /// rows), pay for one ordering. The first is given the load step's node order to
  /// compare with AMD's: made on the same nodes, it had a third fewer flops at 1e5 dof in
  /// 2D; where the points moved into denser couplings during the step it fits badly and
  /// the solver's own is kept (docs/performance.md).
  std::unique_ptr<HelmholtzSmoother<dim>> smoother(double l, const std::vector<int>& held) {
    const bool first = ordered_ == nullptr;
    std::vector<int> ordering = first ? load_step_ordering() : ordered_->ordering();
    auto sm = std::make_unique<HelmholtzSmoother<dim>>(assembler_, pattern_, l, held, backend_, split_,
                                                       std::move(ordering), first);
    if (first) ordered_ = &sm->solver();
    return sm;
  }

  /// The scalar equations in the load step's node order, the nodes it did not solve for
  /// last (serially; a distributed run's solver orders its own rows: none).
  std::vector<int> load_step_ordering() const {
    if (node_order_.empty() || split_) return {};
    return dofs_.equations_in_node_order(node_order_);
  }

  /// Whether the model holds a distributed run's rank's points (the driver's ownership).
  static bool owned_points(const Model<dim>& m) {
    if (!ranks::distributed()) return false;
    if (m.point_ids.size() != static_cast<std::size_t>(m.points.size()))
      throw std::logic_error("gradient step: a distributed run's points must be owned (own_rank_points)");
    return true;
  }
  /// The stencils of the points; points outside the grid end the run as a solver failure
  /// (no cut of the next step could bring them back), on every rank of a distributed run.
  PointStencils<dim> stencils(const Model<dim>& m) const {
    try {
      return evaluate_stencils(m.grid, m.points, m.basis, split_ ? &m.point_ids : nullptr);
    } catch (const std::out_of_range& e) {
      throw SolverError(fmt::format("gradient step: {}", e.what()));
    }
  }

  const Model<dim>& model_;
  double l_;
  LinearSolverSettings backend_;
  std::vector<int> node_order_;  ///< the load step's, by grid node (may be empty)
  bool split_;                 ///< distributed: each rank assembles its points' share (HelmholtzSmoother)
  PointStencils<dim> st_;
  DofMap dofs_;
  Assembler<dim> assembler_;
  SparseMatrix pattern_;
  std::unique_ptr<HelmholtzSmoother<dim>> natural_, projector_;
  std::optional<Vector> lumped_;  ///< nodal masses (per unit density) when the consistent projection is singular
  std::optional<RowHalo> halo_;   ///< a distributed run's rows for the lumped projection
  std::map<std::vector<int>, std::unique_ptr<HelmholtzSmoother<dim>>> by_constraints_;
  const LinearSolver* ordered_ = nullptr;  ///< the solver of the first smoother made (smoother())
};

/// Jacobian that turns the material's stress measure into Cauchy stress.
template <int dim>
double stress_jacobian(const Model<dim>& m, int p) {
  return m.material_of(p).finite_strain() ? m.points.F[p].determinant() : 1.0;
}

/// u-RA: smoothed displacement (increment or total) at the points and its gradient in
/// the points' current configuration. u-RA's strain is the small-strain measure
/// sym grad u_g, as in the 1D foundation; on a configuration that has moved since the
/// classical strain was measured the two measures differ by O(strain^2).
template <int dim>
void smooth_displacement(SmoothingContext<dim>& ctx, const std::vector<Vec<dim>>& u, std::vector<Vec<dim>>& ug,
                         std::vector<Mat3>& grad) {
  const std::size_t n = u.size();
  ug.assign(n, Vec<dim>::Zero());
  grad.assign(n, Mat3::Zero());
  std::vector<double> c(n), value;
  std::vector<Vec<dim>> gradient;
  for (int i = 0; i < dim; ++i) {
    for (std::size_t p = 0; p < n; ++p) c[p] = u[p][i];
    ctx.interpolate(ctx.smooth_displacement(c, i), value, gradient);
    for (std::size_t p = 0; p < n; ++p) {
      ug[p][i] = value[p];
      for (int j = 0; j < dim; ++j) grad[p](i, j) = gradient[p][j];
    }
  }
}

Mat3 sym(const Mat3& g) { return 0.5 * (g + g.transpose()); }

/// Completes the enriched fields from the smoothed one: stress from strain (u-RA, e-RA)
/// or strain from stress (s-RA), with the material's elasticity.
template <int dim>
void complete(const Model<dim>& m, GradientVariant v, EnrichedFields<dim>& f) {
  const int np = m.points.size();
#pragma omp parallel for schedule(static) if (use_threads(np))
  for (int p = 0; p < np; ++p) {
    const IsotropicElasticity& mat = m.material_of(p).elasticity();
    const double J = stress_jacobian(m, p);
    if (v == GradientVariant::S_RA)
      f.strain[p] = mat.strain(J * f.stress[p]);
    else
      f.stress[p] = mat.stress(f.strain[p]) / J;
  }
}

}  // namespace

template <int dim>
EnrichedFields<dim> smooth_total(const Model<dim>& m, const GradientSettings& s, const std::vector<int>& node_order) {
  EnrichedFields<dim> f;
  const int n = m.points.size();
  f.resize(n);
  std::vector<Vec<dim>> u(n);
  for (int p = 0; p < n; ++p) u[p] = m.points.position[p] - m.points.original_position[p];
  if (s.variant == GradientVariant::None) {
    f.displacement = u;
    f.strain = m.elastic_strains();
    f.stress = m.points.stress;
    return f;
  }
  SmoothingContext<dim> ctx(m, s.length_scale, s.linear_solver, node_order);
  switch (s.variant) {
    case GradientVariant::U_RA: {
      std::vector<Mat3> grad;
      smooth_displacement(ctx, u, f.displacement, grad);
      for (int p = 0; p < n; ++p) f.strain[p] = sym(grad[p]);
      break;
    }
    case GradientVariant::E_RA:
      f.displacement = u;
      f.strain = ctx.smooth_tensor(m.elastic_strains());
      break;
    case GradientVariant::S_RA:
      f.displacement = u;
      f.stress = ctx.smooth_tensor(m.points.stress);
      break;
    default:
      break;
  }
  complete(m, s.variant, f);
  f.solver_seconds = ctx.solver_seconds();
  return f;
}

template <int dim>
GradientTracker<dim>::GradientTracker(const Model<dim>& m, const GradientSettings& s)
    : settings_(s),
      prev_position_(m.points.position),
      prev_strain_(m.elastic_strains()),
      prev_stress_(m.points.stress) {
  fields_.resize(m.points.size());
  fields_.strain = prev_strain_;
  fields_.stress = m.points.stress;
  for (int p = 0; p < m.points.size(); ++p)
    fields_.displacement[p] = m.points.position[p] - m.points.original_position[p];
}

template <int dim>
void GradientTracker<dim>::after_step(const Model<dim>& m, const std::vector<int>& node_order) {
  const auto t0 = Clock::now();
  const int n = m.points.size();
  const GradientVariant v = settings_.variant;
  std::vector<Mat3> eps = m.elastic_strains();  // the classical strain, once per step
  if (v != GradientVariant::U_RA)               // e-RA, s-RA and none keep the classical displacement
    for (int p = 0; p < n; ++p) fields_.displacement[p] = m.points.position[p] - m.points.original_position[p];
  if (v == GradientVariant::None) {
    fields_.strain = eps;
    fields_.stress = m.points.stress;
  } else {
    SmoothingContext<dim> ctx(m, settings_.length_scale, settings_.linear_solver, node_order);
    if (v == GradientVariant::U_RA) {
      std::vector<Vec<dim>> du(n), dug;
      std::vector<Mat3> grad;
      for (int p = 0; p < n; ++p) du[p] = m.points.position[p] - prev_position_[p];
      smooth_displacement(ctx, du, dug, grad);
      for (int p = 0; p < n; ++p) {
        fields_.displacement[p] += dug[p];
        fields_.strain[p] += sym(grad[p]);
      }
    } else {
      const bool strain = v == GradientVariant::E_RA;
      std::vector<Mat3> d(n);
      for (int p = 0; p < n; ++p)
        d[p] = strain ? Mat3(eps[p] - prev_strain_[p]) : Mat3(m.points.stress[p] - prev_stress_[p]);
      const std::vector<Mat3> g = ctx.smooth_tensor(d);
      for (int p = 0; p < n; ++p) (strain ? fields_.strain[p] : fields_.stress[p]) += g[p];
    }
    complete(m, v, fields_);
  }
  prev_position_ = m.points.position;
  prev_strain_ = std::move(eps);
  prev_stress_ = m.points.stress;
  seconds_ += seconds_since(t0);
}

template <int dim>
void GradientTracker<dim>::save(Archive& a, const std::string& prefix) const {
  a.put_objects(prefix + "displacement", fields_.displacement);
  a.put_objects(prefix + "strain", fields_.strain);
  a.put_objects(prefix + "stress", fields_.stress);
  a.put_objects(prefix + "previous_position", prev_position_);
  a.put_objects(prefix + "previous_strain", prev_strain_);
  a.put_objects(prefix + "previous_stress", prev_stress_);
}

template <int dim>
void GradientTracker<dim>::restore(const Archive& a, const std::string& prefix) {
  const long long n = a.integer("points/count");  // (a distributed restart: this rank's points now)
  a.get_objects(prefix + "displacement", n, fields_.displacement);
  a.get_objects(prefix + "strain", n, fields_.strain);
  a.get_objects(prefix + "stress", n, fields_.stress);
  a.get_objects(prefix + "previous_position", n, prev_position_);
  a.get_objects(prefix + "previous_strain", n, prev_strain_);
  a.get_objects(prefix + "previous_stress", n, prev_stress_);
}

template <int dim>
void GradientTracker<dim>::migrate(const PointMigration& migration) {
  for (auto* a : {&fields_.strain, &fields_.stress, &prev_strain_, &prev_stress_}) migration.apply(*a);
  migration.apply(fields_.displacement);
  migration.apply(prev_position_);
}

template <int dim>
void GradientStep<dim>::migrate(const PointMigration& migration) {
  if (tracker_) tracker_->migrate(migration);
  if (latest_) {  // (recomputed after the step that migrates: moved only to stay the points')
    for (auto* a : {&latest_->strain, &latest_->stress}) migration.apply(*a);
    migration.apply(latest_->displacement);
  }
}

template <int dim>
void GradientStep<dim>::save(Archive& a) const {
  if (tracker_) tracker_->save(a, name() + "/");
}

template <int dim>
void GradientStep<dim>::restore(const Archive& a) {
  if (tracker_) tracker_->restore(a, name() + "/");
}

template <int dim>
GradientStep<dim>::GradientStep(const Model<dim>& m, const GradientSettings& s) : settings_(s) {
  if (enabled() && s.fields == GradientFields::Points) tracker_.emplace(m, s);
}

template <int dim>
void GradientStep<dim>::after_step(Model<dim>& m, const StepInfo& info) {
  if (!enabled()) return;
  if (tracker_) {
    tracker_->after_step(m, info.after.ordering.nodes);
  } else if (info.last || settings_.apply == GradientApply::EachStep) {
    const auto t0 = Clock::now();
    latest_ = smooth_total<dim>(m, settings_, info.after.ordering.nodes);
    seconds_ += seconds_since(t0);
  }
}

template <int dim>
const EnrichedFields<dim>* GradientStep<dim>::fields() const {
  if (tracker_) return &tracker_->fields();
  return latest_ ? &*latest_ : nullptr;
}

template EnrichedFields<1> smooth_total<1>(const Model<1>&, const GradientSettings&, const std::vector<int>&);
template EnrichedFields<2> smooth_total<2>(const Model<2>&, const GradientSettings&, const std::vector<int>&);
template EnrichedFields<3> smooth_total<3>(const Model<3>&, const GradientSettings&, const std::vector<int>&);
template class GradientTracker<1>;
template class GradientTracker<2>;
template class GradientTracker<3>;
template class GradientStep<1>;
template class GradientStep<2>;
template class GradientStep<3>;

}  // namespace gradmpm
