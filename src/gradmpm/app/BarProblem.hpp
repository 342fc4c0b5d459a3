#pragma once
// The bi-material bar of the paper (section 2, Figure 2), solved as the special case
// of the MPM whose material points sit at Gauss positions and do not move (= FEM):
//   1. classical solve  (E u')' = 0,  u(0) = 0, u(L) = delta            (eq. 6 in 1D)
//   2. gradient step    (M + l^2 L) g = f  for the chosen variant          (eq. 7 and analogues)
// See docs/physics-1d.md for the equations, boundary conditions and recovery.
#include <vector>

#include "gradmpm/gradient/Variant.hpp"
#include "gradmpm/materials/LinearElastic.hpp"
#include "gradmpm/points/MaterialPoints.hpp"
#include "gradmpm/solver/linear/LinearSolverSettings.hpp"

namespace gradmpm {

struct BarConfig {
  double length = 10.0;
  int elements = 80;
  double split = 0.5;  ///< fraction of the length where the material changes
  double young_left = 1000.0;
  double young_right = 5000.0;
  double end_displacement = 0.1;
  int points_per_element = 2;  ///< Gauss points per element (1..4)
  GradientVariant variant = GradientVariant::U_RA;
  double length_scale = 2.0;
  LinearSolverSettings solver;
};

struct BarTimings {
  double assembly_s = 0;         ///< points, shape functions, pattern, stiffness
  double classical_solve_s = 0;  ///< analysis + factorisation + solve of K
  double gradient_s = 0;         ///< (M + l^2 L): assembly, factorisation, smoothing solve
  double recovery_s = 0;         ///< nodal recovery, displacement of e-RA/s-RA, element strains
};

struct BarResult {
  // --- at the grid nodes
  std::vector<double> x;
  Vector u_classical, u_gradient;
  Vector strain_classical, strain_gradient;
  Vector stress_classical, stress_gradient;
  // --- at the material points
  MaterialPoints<1> points;
  std::vector<LinearElastic> materials;  ///< indexed by points.material (0 left, 1 right); nu = 0
  std::vector<double> point_young;
  std::vector<double> point_strain_classical, point_strain_gradient;
  std::vector<double> point_stress_classical, point_stress_gradient;
  // --- per element (derivative of the nodal displacement, constant in each element)
  std::vector<double> element_midpoint;
  std::vector<double> element_strain_classical, element_strain_gradient;

  BarTimings timings;
  int dofs = 0;
  /// MPM runs only: the original position X of the material now at each node (the
  /// closed form is written in X); empty for the FEM bar, where X = x.
  std::vector<double> material_x;
};

/// Solves the bar; throws SolverError on a failed factorisation.
BarResult solve_bar(const BarConfig& config);

}  // namespace gradmpm
