#pragma once
// Closed-form solutions of the bi-material bar (paper, Figure 2; docs/physics-1d.md):
// a bar 0 <= x <= L with E = E1 for x < a and E = E2 for x > a, u(0) = 0, u(L) = delta.
namespace gradmpm::analytic {

struct BimaterialBar {
  double length;            ///< L
  double interface;         ///< a = split * L
  double young_left;        ///< E1
  double young_right;       ///< E2
  double end_displacement;  ///< delta

  /// Classical: the stress is uniform, sigma = delta / (a/E1 + (L-a)/E2).
  double classical_stress() const;
  /// Classical strain sigma/E; at x == a the right-hand value is returned.
  double classical_strain(double x) const;
  double classical_displacement(double x) const;

  /// Gradient strain of e-RA (natural ends) and of u-RA (Dirichlet ends), which
  /// coincide: eps1 + A cosh(x/l) for x <= a, eps2 + B cosh((L-x)/l) for x >= a,
  /// A = -(eps1-eps2) sinh((L-a)/l)/sinh(L/l), B = (eps1-eps2) sinh(a/l)/sinh(L/l).
  /// l == 0 returns the classical strain.
  double gradient_strain(double x, double l) const;
  /// u_g(x) = integral_0^x eps_g (u-RA's displacement; u_g(L) = delta).
  double gradient_displacement(double x, double l) const;
};

}  // namespace gradmpm::analytic
