#pragma once
// The pore water of a saturated soil ([pore_pressure], [materials.NAME] fluid keys,
// [[pressure_constraints]]; docs/pore-pressure.md): what the coupled displacement-pressure
// step (mpm/Consolidation.hpp) needs besides the solid's model.
#include <cmath>
#include <optional>
#include <vector>

namespace gradmpm {

/// The pore fluid and the permeability of one material.
struct PoreFluid {
  /// Hydraulic conductivity k (m/s), as geotechnical engineers give it: Darcy's
  /// q = -k grad h = -(k / gamma_w) (grad p - rho_w g).
  double conductivity = 0.0;
  double bulk_modulus = 2.2e9;  ///< K_f of the pore fluid (water: 2.2e9 Pa)
  double porosity = 0.0;        ///< n_0, at the start (the current one follows the volume: 1 - (1 - n_0) / J)
  double density = 1000.0;      ///< rho_w
  /// k follows the porosity by Kozeny-Carman, k = k_0 (n^3 / (1 - n)^2) / (n_0^3 / (1 -
  /// n_0)^2), n the current porosity; false: k constant.
  bool kozeny_carman = false;

  /// The conductivity at porosity n.
  double conductivity_at(double n) const {
    if (!kozeny_carman) return conductivity;
    const double n0 = porosity;
    return conductivity * (n * n * n / ((1.0 - n) * (1.0 - n))) / (n0 * n0 * n0 / ((1.0 - n0) * (1.0 - n0)));
  }
};

/// A node's pore pressure held at `value` (a drained face: 0); `block`: its
/// [[pressure_constraints]] block.
struct PressureConstraint {
  int node;
  double value = 0.0;
  int block = 0;
};

struct PoreSettings {
  /// drained: no pore pressure (the solid alone, the materials' effective stress is the total
  /// stress); undrained: the pore pressure without flow (k = 0), in load steps; coupled:
  /// consolidation, Darcy flow over time steps ([time] with inertia = false).
  enum class Drainage { Drained, Undrained, Coupled };
  Drainage drainage = Drainage::Drained;
  std::vector<PoreFluid> fluids;  ///< one per material (Model::materials' order)
  std::vector<PressureConstraint> constraints;
  /// tau of the polynomial pressure projection (Dohrmann & Bochev 2004; White & Borja
  /// 2008): tau / (2 G) sum_p V_p (q - Pi q)(dp - Pi dp) in the mass balance, Pi the mean over
  /// the points that share a stencil (a cell's, for the linear basis). Stabilises the
  /// equal-order pressure where the inf-sup condition fails (undrained, the first steps).
  double stabilisation = 1.0;
  /// |g| of gamma_w = rho_w |g|: the case's gravity, or 9.80665 where it has none (a
  /// weightless analysis still needs gamma_w to turn k into a permeability).
  double gravity = 9.80665;
  /// The water table's elevation (its coordinate against gravity): the hydrostatic pressure
  /// below it is where [initial_stress] starts p and what the excess pore pressure is
  /// measured from (mpm/InitialStress.hpp). None: not given.
  std::optional<double> water_table;

  bool active() const { return drainage != Drainage::Drained; }
  bool flows() const { return drainage == Drainage::Coupled; }
};

}  // namespace gradmpm
