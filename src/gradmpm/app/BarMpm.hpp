#pragma once
// The bi-material bar of the foundation issue solved by the implicit MPM
// (examples/bar_bimaterial_mpm.toml): the same [bar] and [gradient] keys plus [mpm]
// (load steps, basis), and the same bar.csv / bar_points.csv / bar.png outputs, so that
// the FEM and MPM answers can be compared directly.
#include "gradmpm/app/BarProblem.hpp"
#include "gradmpm/gradient/MpmGradient.hpp"
#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/io/StagedOutputs.hpp"

namespace gradmpm {

struct BarMpmConfig {
  BarConfig bar;
  GradientSettings gradient;
  int load_steps = 10;
  BasisKind basis = BasisKind::MPM;
};

/// Solves the bar as MPM: points at the Gauss positions (mpm basis) or at sub-cell
/// centres (GIMP), small-strain linear elasticity, the pull applied to every grid node at
/// or beyond x = L. Nodal values are recovered from the points (points/Transfer.hpp) on
/// the nodes the material covers.
/// The largest compression (|end_displacement| with end_displacement < 0) the bar as MPM
/// represents: the grid nodes held at the end displacement are those at or beyond x = L,
/// so the bar's last point must stay in the cell left of x = L (with the mpm basis) or its
/// domain reach into it (GIMP); beyond, nothing holds the end, and the answer is wrong.
double bar_mpm_largest_compression(const BarMpmConfig& c);

BarResult solve_bar_mpm(const BarMpmConfig& c, double* gradient_seconds = nullptr, double* classical_seconds = nullptr);

}  // namespace gradmpm
