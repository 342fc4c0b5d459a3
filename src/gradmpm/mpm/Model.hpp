#pragma once
// Everything an implicit quasi-static MPM analysis needs: the background grid, the
// material points, the materials, the basis, the loads and the grid constraints.
#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gradmpm/basis/BasisKind.hpp"
#include "gradmpm/grid/Grid.hpp"
#include "gradmpm/grid/RankBoxes.hpp"
#include "gradmpm/materials/Material.hpp"
#include "gradmpm/points/MaterialPoints.hpp"
#include "gradmpm/solver/linear/LinearSolverSettings.hpp"

namespace gradmpm {

/// A grid-node displacement component held at `total` (reached at load factor 1,
/// ramped linearly; 0 for a fixed or roller support).
struct NodalConstraint {
  int node;
  int component;
  double total = 0.0;
  bool roller = false;  ///< from a block that holds some but not all components (symmetry, frictionless)
  /// false: a support that only removes rigid motion (a pinned node), not a boundary of
  /// the body: the gradient step keeps its natural condition there (u-RA holds no value,
  /// e-RA and s-RA hold no odd component), so the smoothed field has no spike at it.
  bool gradient_boundary = true;
};

/// Grid nodes whose reaction force and displacement are reported (a named [[constraints]] block).
struct NamedNodeSet {
  std::string name;
  std::vector<int> nodes;
};

/// A rigid, frictionless, axis-aligned box pushing the material points by penalty contact
/// (a footing, a platen, an indenter; mpm/RigidContact.hpp).
template <int dim>
struct RigidBox {
  std::string name;                   ///< reported in reactions.csv when not empty
  Vec<dim> lo, hi;                    ///< the box at load factor 0
  Vec<dim> total = Vec<dim>::Zero();  ///< its displacement at load factor 1
  double stiffness = 0.0;             ///< k: contact pressure per unit penetration
};

/// The implicit-gradient regularisation of the softening laws ([regularisation];
/// mpm/ImplicitGradient.hpp). The laws themselves are made regularised
/// (Material::regularised); these are the settings of the nonlocal field they share.
struct Regularisation {
  double length_scale = 0.0;  ///< l of kappa_bar - l^2 laplacian kappa_bar = kappa
  /// Where kappa_bar starts each load step's staggered iteration: kept at the points from
  /// the end of the last step (true), or recomputed from kappa_n on the new step's grid.
  bool start_from_points = true;
  int max_iterations = 100;  ///< staggered iterations per load step before it is cut
  double tolerance = 1e-6;   ///< on max |d kappa_bar| / max kappa_bar of a staggered iteration
};

template <int dim>
struct Model {
  Grid<dim> grid;
  MaterialPoints<dim> points;
  std::vector<std::shared_ptr<const Material>> materials;
  BasisKind basis = BasisKind::MPM;
  bool fbar = false;                    ///< F-bar against volumetric locking (mpm/FBar.hpp); finite-strain laws only
  double ghost_penalty = 0.0;           ///< alpha of the ghost stabilisation (mpm/GhostPenalty.hpp); 0 = off
  Vec<dim> gravity = Vec<dim>::Zero();  ///< acceleration at load factor 1 (body force m_p g)
  std::vector<NodalConstraint> constraints;
  /// Planes x_axis = position of roller blocks that hold their normal component (symmetry
  /// planes, frictionless supports): the gradient step holds the odd shear components at
  /// zero on their nodes, fixed-support nodes on them included.
  std::vector<std::pair<int, double>> roller_planes;
  std::vector<NamedNodeSet> node_sets;
  std::vector<RigidBox<dim>> rigid_boxes;
  Regularisation regularisation;
  /// A distributed run's points are owned (mpm/PointMigration.hpp): `points` holds this
  /// rank's, and its point k is point point_ids[k] of the whole body (increasing; its row
  /// of points_final.csv). Empty while `points` holds every point in id order (a serial run).
  std::vector<int> point_ids;
  /// A distributed run's cut of the grid into boxes of cells, one per rank (rank r owns
  /// the cells and nodes rank_boxes.owner() gives it: grid/RankBoxes.hpp,
  /// mpm/RankPoints.hpp); fixed for the run. Set once the points are owned (empty: every
  /// rank holds every point).
  RankBoxes rank_boxes;

  explicit Model(const Grid<dim>& g) : grid(g) {}

  /// Sizes the points' state block for the materials and writes every point's initial
  /// state. The driver calls it when the block does not match (a model built in code).
  void initialise_state() {
    const int stride = state_stride();
    points.state_stride = stride;
    points.state.assign(static_cast<std::size_t>(points.size()) * stride, 0.0);
    for (int p = 0; p < points.size(); ++p) materials[points.material[p]]->initial_state(points.state_of(p));
  }
  bool state_initialised() const {
    return points.state_stride == state_stride() &&
           points.state.size() == static_cast<std::size_t>(points.size()) * points.state_stride;
  }
  /// The largest state of the materials: values per point in the state block.
  int state_stride() const {
    int stride = 0;
    for (const auto& m : materials) stride = std::max(stride, m->state_size());
    return stride;
  }
  /// false when some material's consistent tangent is not symmetric (or F-bar is on).
  bool symmetric_tangent() const {
    if (fbar) return false;
    for (const auto& m : materials)
      if (!m->symmetric_tangent()) return false;
    return true;
  }
  /// Point p's number in the whole body.
  int id_of(int p) const { return point_ids.empty() ? p : point_ids[p]; }
  const Material& material_of(int p) const { return *materials[points.material[p]]; }
  /// Calls f(state) with point p's state (its material's initial state before the state
  /// block is initialised).
  template <class F>
  auto with_state(int p, F&& f) const {
    if (state_initialised()) return f(points.state_of(p));
    std::vector<double> initial(material_of(p).state_size());
    material_of(p).initial_state(initial.data());
    return f(static_cast<const double*>(initial.data()));
  }
  /// The elastic strain of point p (from its material's state).
  Mat3 elastic_strain(int p) const {
    return with_state(p, [&](const double* s) { return material_of(p).elastic_strain(s); });
  }
  /// The elastic energy stored at point p: its material's density (finite strain: per
  /// reference volume) on V_p, or on v_p for a small-strain law. The point has dissipated
  /// its work (MaterialPoints::work) less this.
  double elastic_energy(int p) const {
    const Material& mat = material_of(p);
    const double density = with_state(p, [&](const double* s) { return mat.elastic_energy_density(s); });
    return density * (mat.finite_strain() ? points.original_volume[p] : points.volume[p]);
  }
  std::vector<Mat3> elastic_strains() const {
    std::vector<Mat3> e(points.size());
    for (int p = 0; p < points.size(); ++p) e[p] = elastic_strain(p);
    return e;
  }
};

struct NewtonSettings {
  int load_steps = 1;
  double tolerance = 1e-9;  ///< on |r_free| / max(|f_ext|, |f_int|)
  int max_iterations = 25;
  int max_cuts = 6;  ///< halvings of a failing load increment before giving up
  /// A direct solver keeps its symbolic analysis for the next load step when that step's
  /// pattern is the same (the answer is the same to the bit; off only to test that).
  bool reuse_analysis = true;
  /// When the pattern has changed, the analysis takes the previous step's fill-reducing
  /// ordering, carried through the grid nodes, unless the pattern's entries changed by
  /// more than 10 % or the fill exceeds by 10 % that of the last ordering computed afresh
  /// (then it orders afresh): the ordering (AMD, METIS) is most of an analysis. The
  /// answer is the same to round-off (off only to test that).
  bool reuse_ordering = true;
  /// Where a load step's symbolic analysis runs: on the calling thread beside its first
  /// tangent's assembly on the other threads where the last measured analysis and
  /// tangent say it pays (Measured), always there (Always), or after the assembly (Never).
  /// The answer is the same to the bit (Always and Never only to test that).
  enum class AnalysisBeside { Measured, Always, Never } analysis_beside = AnalysisBeside::Measured;
  LinearSolverSettings linear_solver;
};

/// Seconds spent in each phase of a load step (summed over its Newton iterations).
struct PhaseTimes {
  double pattern = 0;   ///< shape functions, active nodes, sparsity pattern, f_ext
  double assembly = 0;  ///< point loop: material updates, f_int and tangent scatter-add
  double analysis = 0;  ///< symbolic factorisation (once per load step)
  double factor = 0;    ///< numeric factorisations
  double solve = 0;     ///< triangular solves
  double update = 0;    ///< mapping the increment to the points, updating their state
  double nonlocal = 0;  ///< regularised plasticity: the Helmholtz operator and the kappa_bar solves
  int iterations = 0;   ///< Newton iterations (linear solves)
  int analyses = 0;     ///< symbolic analyses (0 in a step whose pattern the previous step had)
  int orderings = 0;    ///< of which with an ordering computed afresh (the others took the previous step's)
  int beside = 0;       ///< of which beside the first tangent's assembly (NewtonSettings::analysis_beside)
  long krylov = 0;      ///< Krylov iterations of those solves (an iterative linear solver; 0 for a direct one)
  PhaseTimes& operator+=(const PhaseTimes& o) {
    pattern += o.pattern;
    assembly += o.assembly;
    analysis += o.analysis;
    factor += o.factor;
    solve += o.solve;
    update += o.update;
    nonlocal += o.nonlocal;
    iterations += o.iterations;
    analyses += o.analyses;
    orderings += o.orderings;
    beside += o.beside;
    krylov += o.krylov;
    return *this;
  }
};

struct RunSummary {
  int steps = 0;
  int total_iterations = 0;
  int cuts = 0;
};

/// The last analysis's ordering, which the next load step's analysis starts from
/// (NewtonSettings::reuse_ordering; empty for iterative solvers).
struct CarriedOrdering {
  std::vector<int> nodes;  ///< the grid nodes in the order their equations were eliminated
  double fill = 0.0;       ///< entries of the factor per entry of the matrix, of the last ordering computed afresh
  double entries = 0.0;    ///< the matrix's entries at the last analysis
};

/// Where the driver stands between two load steps: with the model (and the post-step
/// stages' state), everything a restarted run needs to continue bit for bit.
struct DriverState {
  double load_factor = 0.0;     ///< lambda reached
  double next_increment = 0.0;  ///< d lambda the next step tries first (0: the nominal one)
  RunSummary summary;           ///< of the steps so far
  CarriedOrdering ordering;     ///< what the next step's analysis starts from
};

/// What one converged load step did; passed to the observer after every step.
struct StepInfo {
  int step = 0;                          ///< 1, 2, ... (converged steps)
  double load_factor = 0.0;              ///< lambda at the end of the step
  double increment = 0.0;                ///< d lambda of the step
  int cuts = 0;                          ///< halvings needed before this step converged
  std::vector<std::string> cut_reasons;  ///< why each of those attempts failed
  std::vector<double> residuals;         ///< normalised out-of-balance force per Newton iteration
  int staggers = 0;                      ///< staggered iterations of kappa_bar (regularised plasticity; 0 without)
  int indefinite_solves =
      0;  ///< iterations whose symmetric tangent was not positive definite (solved by linear_solver.general)
  int backtracks = 0;  ///< halvings of Newton corrections that inverted a point (the converged attempt)
  int migrated = 0;    ///< a distributed run: points that changed rank after the step (all ranks')
  bool last = false;   ///< the step that reaches load factor 1
  DriverState after;   ///< the driver's state after this step (what a checkpoint of it records)
  /// Grid fields of the step, computed only when called (outputs ask for them on the
  /// steps they write); valid during the post-step stages and the observer call only.
  /// A distributed run's are at the nodes grid_nodes() lists only (the active nodes the
  /// rank knows, value k at the k-th), right at the nodes the rank owns
  /// (Model::rank_boxes) and at the corners of its cells, and the first call of the four
  /// is collective (every rank must make it: the corners other ranks own are fetched
  /// from them). Serially grid_nodes() is empty: the values are at every grid node.
  std::function<std::vector<int>()> grid_nodes;
  std::function<const Vector&()> grid_displacement;  ///< the step's displacement increment at every grid node (dim per node)
  std::function<const Vector&()> grid_mass;       ///< nodal mass sum_p N_i m_p (eq. 1)
  std::function<std::vector<bool>()> grid_active;  ///< the nodes the step solved for (in some point's stencil)
  /// f_int - f_ext at the converged iterate at every grid node (dim per node): the
  /// reaction forces on constrained components (~0 elsewhere; zero on inactive nodes).
  std::function<const Vector&()> grid_reaction;
  /// The force each rigid box exerts on the body at the converged iterate (dim per box).
  std::function<Vector()> rigid_forces;
  double seconds = 0.0;        ///< the load step, its cuts included, without the post-step stages
  double stage_seconds = 0.0;  ///< the post-step stages
  PhaseTimes phases;           ///< of the converged attempt
  int dofs = 0;                ///< equations of the step
  long nonzeros = 0;           ///< entries of the tangent
};

/// Where node n's values are among a distributed run's listed nodes (ascending, as
/// StepInfo::grid_nodes() gives them): its position, or -1 if it is not listed.
inline int listed_position(const std::vector<int>& listed, int n) {
  const auto it = std::lower_bound(listed.begin(), listed.end(), n);
  return it == listed.end() || *it != n ? -1 : static_cast<int>(it - listed.begin());
}

}  // namespace gradmpm
