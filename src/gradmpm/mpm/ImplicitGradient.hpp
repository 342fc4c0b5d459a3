#pragma once
// Implicit-gradient plasticity (docs/shear-bands.md; Peerlings et al. 1996 for damage,
// Engelen, Geers & Baaijens 2003 and Jirasek & Rolshoven 2003 for plasticity): the
// softening of a regularised law is driven by the over-nonlocal variable
//     kappa_hat = (1 - m) kappa + m kappa_bar,   m > 1,
// where the nonlocal equivalent plastic strain kappa_bar solves the Helmholtz equation
// of the Ru-Aifantis step,
//     kappa_bar - l^2 laplacian kappa_bar = kappa,   (M + l^2 L) kappa_bar = sum_p N kappa_p V_p,
// on the load step's grid with the case's basis, integrated by the regularised points at
// x_n (natural boundary grad kappa_bar . n = 0 on the boundary of that material).
//
// The coupling is staggered within each load step (mpm/QuasiStatic.cpp): Newton on the
// displacements with kappa_bar frozen (each point's return then sees the local modulus
// (1 - m) H, which hardens when H < 0 and m > 1), then kappa_bar from the kappa of the
// converged iterate; repeated until kappa_bar changes by less than [regularisation]
// tolerance (relative to its largest value) and Newton is in balance with it. The converged pair satisfies both
// equations at once, as a monolithic solve would. kappa_bar is not history: it is a function of the current kappa
// field.
//
// The plain fixed point kappa_bar <- G(kappa_bar) does not contract once the band forms:
// with kappa_bar frozen a point's kappa grows by m |H| / (local modulus) > 1 per unit of
// kappa_bar, and only the unloading of the rest of the body holds it back (measured: 100
// iterations did not converge a step past the peak of examples/softening_bar_1d.toml). So
// the iterates are Anderson-accelerated (Walker & Ni 2011, depth 8): the new kappa_bar
// combines the last iterates so as to minimise the fixed-point residual G(x) - x in the
// least-squares sense, a secant method on the few modes that do not contract.
// The driver writes it into the state the step starts from (the slot eps_p_nonlocal of
// a regularised law), where the laws read it.
#include <vector>

#include "gradmpm/gradient/Helmholtz.hpp"
#include "gradmpm/mpm/Model.hpp"
#include "gradmpm/mpm/PointPartition.hpp"
#include "gradmpm/points/Transfer.hpp"
#include "gradmpm/solver/DofMap.hpp"

namespace gradmpm {

template <int dim>
class NonlocalPlasticStrain {
 public:
  /// The operator of the load step whose stencils at x_n are `stencils` (factorised once,
  /// reused by every staggered iteration of the step). In a distributed run `m`'s points
  /// are this rank's (the load step's, mpm/RankPoints.hpp): it assembles their share of
  /// the Helmholtz system, the solver adds the shares up.
  NonlocalPlasticStrain(const Model<dim>& m, const PointStencils<dim>& stencils, const LinearSolverSettings& solver);

  /// kappa_bar from the kappa held in the state block `source`, written into the
  /// kappa_bar slot of every regularised point of `target` (source may be target): the
  /// plain smoothing G(kappa_bar).
  void smooth(const std::vector<double>& source, std::vector<double>& target) const;
  /// One staggered iteration: G of the kappa_bar in `target` from the kappa of the
  /// iterate in `source`, Anderson-accelerated over the step's earlier iterations, written
  /// into `target`. Returns max |change of kappa_bar| / max(max kappa_bar, 1e-300).
  double iterate(const std::vector<double>& source, std::vector<double>& target);

  /// Whether any material of `m` is regularised (declares eps_p_nonlocal).
  static bool applies(const Model<dim>& m);

  // For the monolithic coupling (mpm/GradientCoupling.hpp), which solves the same equation
  // beside the displacements:
  /// The step's stencils of the regularised points, the weak nodes left out (the others' empty).
  const PointStencils<dim>& stencils() const { return stencils_; }
  /// The Helmholtz system's numbering (one unknown per node of stencils()).
  const DofMap& dofs() const { return dofs_; }
  /// kappa_bar at the nodes of dofs() from the kappa held in the state block `source`: G's nodal values.
  Eigen::VectorXd nodal(const std::vector<double>& source) const;
  /// The regularised points, ascending.
  const std::vector<int>& regularised_points() const { return regularised_points_; }
  /// Offsets of kappa (eps_p) and kappa_bar (eps_p_nonlocal) in the state of a point of
  /// material `material` (-1: not regularised).
  int kappa_slot(int material) const { return slots_[material].kappa; }
  int nonlocal_slot(int material) const { return slots_[material].nonlocal; }

 private:
  struct Slots {
    int kappa = -1, nonlocal = -1;  ///< offsets in a point's state; -1: not regularised
  };
  static Slots slots_of(const Material& mat);
  Eigen::VectorXd smoothed(const std::vector<double>& source) const;  ///< G at the regularised points
  Eigen::VectorXd gather(const std::vector<double>& state) const;     ///< kappa_bar of the regularised points
  void scatter(const Eigen::VectorXd& kappa_bar, std::vector<double>& state) const;
  /// A vector over this rank's regularised points, gathered over every rank's (rank order).
  Eigen::VectorXd over_ranks(const Eigen::VectorXd& mine) const;

  static constexpr int kDepth = 8;  ///< iterates Anderson's least squares combines

  const Model<dim>& model_;
  std::vector<Slots> slots_;     ///< per material
  PointStencils<dim> stencils_;  ///< the step's, emptied for points that are not regularised
  DofMap dofs_;
  Assembler<dim> assembler_;
  SparseMatrix pattern_;
  HelmholtzSmoother<dim> smoother_;
  std::vector<int> regularised_points_;
  std::vector<int> counts_;               ///< the regularised points of each rank
  int offset_ = 0;                        ///< this rank's first in the vectors over the ranks
  std::vector<Eigen::VectorXd> dx_, df_;  ///< differences of the last iterates and residuals
  Eigen::VectorXd x_prev_, f_prev_;
};

}  // namespace gradmpm
