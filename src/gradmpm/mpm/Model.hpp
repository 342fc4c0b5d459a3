#pragma once
// Everything an implicit quasi-static MPM analysis needs: the background grid, the
// material points, the materials, the basis, the loads and the grid constraints.
#include <algorithm>
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gradmpm/basis/BasisKind.hpp"
#include "gradmpm/grid/Grid.hpp"
#include "gradmpm/grid/RankBoxes.hpp"
#include "gradmpm/materials/Material.hpp"
#include "gradmpm/mpm/PorePressure.hpp"
#include "gradmpm/points/MaterialPoints.hpp"
#include "gradmpm/solver/nonlinear/NewtonSettings.hpp"

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

/// Two grid nodes whose displacement component moves together, by a penalty stiffness
/// k (u_a - u_b)^2 / 2 ([[ties]]: a rigid frictionless plate under a load, whose nodes
/// share one displacement; Mandel's problem). Serial runs.
struct NodeTie {
  int a, b;
  int component;
  double stiffness;  ///< k: force per unit difference of the two displacements
};

/// Grid nodes whose reaction force and displacement are reported (a named [[constraints]] block).
struct NamedNodeSet {
  std::string name;
  std::vector<int> nodes;
};

/// A named set of material points (`[[point_sets]]`): those in a box at the start, by
/// index. The reports that use it (the degree of consolidation, app/MpmRun.cpp) run on one
/// rank, where a point keeps its index.
struct PointSet {
  std::string name;
  std::vector<int> points;
};

/// A rigid body pushing the material points by penalty contact, frictionless or rough (a
/// footing, a platen, an indenter, a cone; mpm/RigidContact.hpp): an axis-aligned box
/// ([[rigid_boxes]]), or in 2D a convex polygon ([[rigid_bodies]]).
template <int dim>
struct RigidBox {
  std::string name;                   ///< reported in reactions.csv when not empty
  Vec<dim> lo, hi;                    ///< the box at load factor 0 (a polygon's bounding box)
  std::vector<Vec<dim>> polygon;      ///< 2D: a convex polygon's vertices, anticlockwise, at load factor 0; empty: the box
  Vec<dim> total = Vec<dim>::Zero();  ///< its displacement at load factor 1
  double stiffness = 0.0;             ///< k: contact pressure per unit penetration
  double friction = 0.0;              ///< mu: Coulomb's coefficient (0: frictionless)
  double adhesion = 0.0;              ///< a: shear strength at no pressure (a Tresca interface: mu = 0)
};

/// The implicit-gradient regularisation of the softening laws ([regularisation];
/// mpm/ImplicitGradient.hpp). The laws themselves are made regularised
/// (Material::regularised); these are the settings of the nonlocal field they share.
struct Regularisation {
  double length_scale = 0.0;  ///< l of kappa_bar - l^2 laplacian kappa_bar = kappa
  /// Where kappa_bar starts each load step's staggered iteration: kept at the points from
  /// the end of the last step (true), or recomputed from kappa_n on the new step's grid.
  bool start_from_points = true;
  /// Displacements and kappa_bar by one Newton iteration (mpm/GradientCoupling.hpp), or
  /// staggered (mpm/ImplicitGradient.hpp).
  bool monolithic = false;
  int max_iterations = 100;  ///< staggered iterations per load step before it is cut
  double tolerance = 1e-6;   ///< on max |d kappa_bar| / max kappa_bar of a staggered iteration
};

/// Implicit dynamics ([time]; mpm/Dynamics.hpp): the grid's equations gain the points'
/// inertia M a (and Rayleigh damping alpha M v), integrated by Newmark or generalised-alpha
/// in time steps dt from t = 0 to end_time. dt = 0: a quasi-static analysis.
struct TimeSettings {
  enum class Scheme { Newmark, GeneralisedAlpha };
  double dt = 0.0;        ///< the nominal time step (cut and grown back as load steps are)
  double end_time = 0.0;  ///< the run ends at t = end_time
  Scheme scheme = Scheme::Newmark;
  double beta = 0.25, gamma = 0.5;  ///< Newmark's (the trapezoidal rule: no numerical damping)
  /// Generalised-alpha's spectral radius at dt -> infinity (Chung & Hulbert 1993): 1
  /// keeps every mode, 0 damps the highest at once.
  double rho_inf = 0.8;
  /// The load factor lambda(t) = min(t / ramp_time, 1); 0: the loads act in full from t = 0
  /// (then no displacement may be prescribed other than 0).
  double ramp_time = 0.0;
  bool consistent_mass = false;  ///< M_ab = sum_p N_a N_b m_p (serial runs); else lumped, m_a = sum_p N_a m_p
  double damping = 0.0;          ///< Rayleigh's mass-proportional alpha (1/s): C = alpha M
  /// theta of the points' velocity update v_p = (1 - theta) v_p,Newmark + theta sum_i N_ip v_i:
  /// the part of v_p the grid cannot see (not an interpolant of nodal values) is kept by
  /// Newmark's update (theta = 0) and never moves anything; theta > 0 lets it decay.
  double pic_fraction = 0.0;
  /// Stop once the kinetic energy has fallen below this fraction of its peak and the
  /// inertia and damping forces below its square root of the forces in balance (not at
  /// an oscillation's turning point); 0: run to end_time. A collapse followed to rest.
  double stop_at_rest = 0.0;
  /// false: time steps without inertia (consolidation, PoreSettings: the time is the flow's).
  bool inertia = true;

  /// Whether the run advances in time (dt > 0), with or without inertia.
  bool dynamic() const { return dt > 0.0; }
  /// Whether the points' inertia is in the equations (mpm/Dynamics.hpp).
  bool inertial() const { return dt > 0.0 && inertia; }
  double load_factor(double t) const { return ramp_time > 0.0 ? std::min(t / ramp_time, 1.0) : 1.0; }
  /// alpha_m, alpha_f, beta, gamma of the scheme (Newmark: alpha_m = alpha_f = 0).
  std::array<double, 4> coefficients() const {
    if (scheme == Scheme::Newmark) return {0.0, 0.0, beta, gamma};
    const double am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0), af = rho_inf / (rho_inf + 1.0);
    const double g = 0.5 - am + af;
    return {am, af, 0.25 * (1.0 - am + af) * (1.0 - am + af), g};
  }
};

template <int dim>
struct Model {
  Grid<dim> grid;
  MaterialPoints<dim> points;
  std::vector<std::shared_ptr<const Material>> materials;
  BasisKind basis = BasisKind::MPM;
  bool fbar = false;                    ///< F-bar against volumetric locking (mpm/FBar.hpp); finite-strain laws only
  double ghost_penalty = 0.0;           ///< alpha of the ghost stabilisation (mpm/GhostPenalty.hpp); 0 = off
  /// 2D axisymmetric (r-z): x is the radius r > 0, y the axis z; the out-of-plane
  /// component is the hoop one (strain u_r / r); volumes, masses, forces and reactions are
  /// per radian (docs/axisymmetry.md).
  bool axisymmetric = false;
  Vec<dim> gravity = Vec<dim>::Zero();  ///< acceleration at load factor 1 (body force m_p g)
  /// Gravity acts in full from the first step, not ramped with the load factor: the points
  /// start from an initial stress in balance with it ([initial_stress], mpm/InitialStress.hpp).
  bool dead_gravity = false;
  std::vector<NodalConstraint> constraints;
  /// Planes x_axis = position of roller blocks that hold their normal component (symmetry
  /// planes, frictionless supports): the gradient step holds the odd shear components at
  /// zero on their nodes, fixed-support nodes on them included.
  std::vector<std::pair<int, double>> roller_planes;
  std::vector<NamedNodeSet> node_sets;
  std::vector<PointSet> point_sets;
  std::vector<NodeTie> ties;  ///< [[ties]]: node pairs held together by a penalty
  std::vector<RigidBox<dim>> rigid_boxes;
  Regularisation regularisation;
  TimeSettings time;  ///< implicit dynamics ([time]); time.dt = 0: quasi-static
  PoreSettings pore;  ///< pore water ([pore_pressure]; mpm/Consolidation.hpp); drained by default
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
    for (const auto& b : rigid_boxes)  // sliding couples the shear to the pressure
      if (b.friction > 0.0) return false;
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

struct RunSummary {
  int steps = 0;
  int total_iterations = 0;
  int cuts = 0;
};

/// Where the driver stands between two load steps: with the model (and the post-step
/// stages' state), everything a restarted run needs to continue bit for bit.
struct DriverState {
  double load_factor = 0.0;     ///< lambda reached
  double next_increment = 0.0;  ///< d lambda (a dynamic run: dt) the next step tries first (0: the nominal one)
  double time = 0.0;            ///< a dynamic run's time reached (0 in a quasi-static one)
  double peak_kinetic_energy = 0.0;  ///< a dynamic run's largest kinetic energy so far (TimeSettings::stop_at_rest)
  /// Arc-length control: the last step's increment at every grid node (dim per node; the
  /// predictor's direction), and the largest load factor reached.
  std::vector<double> arc_previous;
  double arc_nominal = 0.0;  ///< the first arc's length, which later arcs grow back to and not beyond
  double peak_load_factor = 0.0;
  RunSummary summary;           ///< of the steps so far
  CarriedOrdering ordering;     ///< what the next step's analysis starts from
};

/// What one converged load step did; passed to the observer after every step.
/// (NewtonLog: its residuals, phase times, indefinite solves and backtracks.)
struct StepInfo : NewtonLog {
  int step = 0;                          ///< 1, 2, ... (converged steps)
  double load_factor = 0.0;              ///< lambda at the end of the step
  double increment = 0.0;                ///< d lambda of the step
  double time = 0.0;                     ///< a dynamic run's time t at the end of the step (0 in a quasi-static one)
  double time_increment = 0.0;           ///< a dynamic run's dt of the step
  double kinetic_energy = 0.0;           ///< a dynamic run's sum of m_p |v_p|^2 / 2 at the end of the step
  /// a dynamic run's |M a + C v| against the larger of |f_ext| and |f_int| at the solution
  double inertia_ratio = 0.0;
  bool at_rest = false;                  ///< a dynamic run stops here: TimeSettings::stop_at_rest reached
  int cuts = 0;                          ///< halvings needed before this step converged
  std::vector<std::string> cut_reasons;  ///< why each of those attempts failed
  int staggers = 0;                      ///< staggered iterations of kappa_bar (regularised plasticity; 0 without)
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
  /// With pore pressure (PoreSettings): p at the step's end at every grid node (zero on
  /// inactive nodes); empty without.
  std::function<const Vector&()> grid_pore_pressure;
  /// The force each rigid box exerts on the body at the converged iterate (dim per box).
  std::function<Vector()> rigid_forces;
  double seconds = 0.0;        ///< the load step, its cuts included, without the post-step stages
  double stage_seconds = 0.0;  ///< the post-step stages
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
