#pragma once
// The Ru-Aifantis gradient step inside the MPM (docs/gradient-study.md).
//
// The split is one-way: the classical MPM solve never sees the gradient fields. After a
// load step (or at the end) a classical field c is smoothed by (M + l^2 L) g = f, with M
// and L integrated by the material points at their current positions and volumes:
//   u-RA  c = displacement, held where the classical problem holds it (at the classical
//         field's nodal values, i.e. the L2 projection of the points' displacement)
//   e-RA  c = strain components, natural boundary (grad g . n = 0 on the grid boundary;
//         see below for the boundary of the material)
//   s-RA  c = stress components, natural boundary
// The operator is scalar: one factorisation serves every component (u-RA: one per
// distinct set of constrained nodes, at most dim).
//
// Where the natural condition holds: M and L only have entries for nodes whose support
// holds material, so the weak form integrates over the material alone, and its natural
// condition grad g . n = 0 applies on the boundary of the material, wherever that lies in
// the grid. No node outside the material enters the system.
//
// `fields`:
//   points  after every load step the *increment* of the classical field is smoothed and
//           accumulated at the points (the enriched fields are point state);
//   grid    the *total* classical field is smoothed whenever it is reported, from the
//           points' current values; nothing is carried between steps.
// `apply`:  each_step (smooth after every load step) or end (once, after the last step).
#include <optional>
#include <string_view>
#include <vector>

#include "gradmpm/gradient/Variant.hpp"
#include "gradmpm/mpm/QuasiStatic.hpp"
#include "gradmpm/solver/linear/LinearSolverSettings.hpp"

namespace gradmpm {

enum class GradientApply { EachStep, End };
enum class GradientFields { Points, Grid };

struct GradientSettings {
  GradientVariant variant = GradientVariant::None;
  double length_scale = 0.0;
  GradientApply apply = GradientApply::EachStep;
  GradientFields fields = GradientFields::Points;
  /// Solver of the Helmholtz systems: the case's [linear_solver], so that a problem too
  /// large to factorise is not factorised by its gradient step either.
  LinearSolverSettings linear_solver;
};

/// The enriched fields at every material point.
template <int dim>
struct EnrichedFields {
  std::vector<Vec<dim>> displacement;  ///< u_g (total)
  std::vector<Mat3> strain;            ///< eps_g (small-strain measure)
  std::vector<Mat3> stress;            ///< sigma_g (Cauchy)
  double solver_seconds = 0.0;         ///< of the time it took, the sparse factorisations and solves
  void resize(int n) {
    displacement.assign(n, Vec<dim>::Zero());
    strain.assign(n, Mat3::Zero());
    stress.assign(n, Mat3::Zero());
  }
};

/// Smooths the total classical field of the model's current state (fields = grid, or
/// apply = end). The displacement of a point is x_p - X_p; u-RA holds the classically
/// constrained node components at the L2 projection of that field. `node_order`: the
/// last load step's elimination order of the grid nodes (StepInfo::after.ordering.nodes), which
/// the Helmholtz systems' analysis compares with its own; empty: none.
template <int dim>
EnrichedFields<dim> smooth_total(const Model<dim>& model, const GradientSettings& s,
                                 const std::vector<int>& node_order = {});

/// Carries the enriched fields at the points through the load steps (fields = points).
template <int dim>
class GradientTracker {
 public:
  GradientTracker(const Model<dim>& model, const GradientSettings& s);
  /// After a converged step: smooths the step's increments of the classical field
  /// (taken at the points) and accumulates them at the points. `node_order`: as for
  /// smooth_total.
  void after_step(const Model<dim>& model, const std::vector<int>& node_order = {});
  const EnrichedFields<dim>& fields() const { return fields_; }
  double seconds() const { return seconds_; }
  /// Its state (the accumulated fields and the classical fields of the last step) under `prefix`.
  void save(Archive& a, const std::string& prefix) const;
  void restore(const Archive& a, const std::string& prefix);
  /// Moves its per-point arrays with the points (a distributed run).
  void migrate(const PointMigration& migration);

 private:
  GradientSettings settings_;
  EnrichedFields<dim> fields_;
  std::vector<Vec<dim>> prev_position_;
  std::vector<Mat3> prev_strain_, prev_stress_;
  double seconds_ = 0.0;
};

/// The gradient step of a run as the settings ask, a post-step stage of the driver:
/// after every converged load step it accumulates the smoothed increments (fields =
/// points) or recomputes the total field (fields = grid: after every step with apply =
/// each_step, after the last with apply = end). When it runs does not depend on the
/// output schedule. Times itself.
template <int dim>
class GradientStep final : public PostStepStage<dim> {
 public:
  GradientStep(const Model<dim>& model, const GradientSettings& s);
  bool enabled() const { return settings_.variant != GradientVariant::None; }
  std::string name() const override { return "gradient"; }
  void after_step(Model<dim>& model, const StepInfo& info) override;
  /// fields = points carries its accumulated fields; fields = grid carries nothing.
  void save(Archive& a) const override;
  void restore(const Archive& a) override;
  void migrate(const PointMigration& migration) override;
  /// The latest enriched fields, or null when none have been computed yet.
  const EnrichedFields<dim>* fields() const;
  double seconds() const { return seconds_ + (tracker_ ? tracker_->seconds() : 0.0); }

 private:
  GradientSettings settings_;
  std::optional<GradientTracker<dim>> tracker_;
  std::optional<EnrichedFields<dim>> latest_;
  double seconds_ = 0.0;
};

}  // namespace gradmpm
