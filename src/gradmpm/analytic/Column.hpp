#pragma once
// Closed form of the elastic column under self-weight (lateral rollers, base fixed,
// Poisson's ratio 0, reference density rho_0, gravity g, height H_0).
//
// Equilibrium alone fixes the vertical Cauchy stress at material height Y:
//     sigma_yy(Y) = -rho_0 g (H_0 - Y)                (the weight of what lies above)
// With Hencky hyperelasticity (Kirchhoff tau = E ln(lambda) for nu = 0, sigma = tau / J,
// J = lambda under lateral confinement) the stretch lambda(Y) solves
//     E ln(lambda) = -lambda q,   q = rho_0 g (H_0 - Y),
// and with dY = E (1 - ln lambda) / (rho_0 g lambda^2) d lambda the position is
//     y(Y) = E/(rho_0 g) [ (ln l - ln^2 l / 2) ]  from l = lambda(0) to l = lambda(Y).
// (A law sigma = E ln(lambda) written for the *Cauchy* stress would instead give
// lambda = exp(-q/E); see docs/mpm.md for why gradmpm's Hencky is the Kirchhoff one.)
namespace gradmpm::analytic {

struct Column {
  double height;   ///< H_0
  double density;  ///< rho_0
  double gravity;  ///< g > 0 (acting downwards)
  double young;    ///< E

  double cauchy_stress(double Y) const { return -density * gravity * (height - Y); }
  /// Stretch lambda(Y) of the Hencky (Kirchhoff) column.
  double stretch(double Y) const;
  /// Current height y of the material at original height Y.
  double position(double Y) const;
  /// Same for a Cauchy-stress log-strain law, sigma = E ln(lambda): lambda = exp(-q/E).
  double position_cauchy_log_law(double Y) const;
};

}  // namespace gradmpm::analytic
