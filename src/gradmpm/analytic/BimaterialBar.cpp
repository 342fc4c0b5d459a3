#include "gradmpm/analytic/BimaterialBar.hpp"

#include <cmath>

namespace gradmpm::analytic {

double BimaterialBar::classical_stress() const {
  return end_displacement / (interface / young_left + (length - interface) / young_right);
}

double BimaterialBar::classical_strain(double x) const {
  return classical_stress() / (x < interface ? young_left : young_right);
}

double BimaterialBar::classical_displacement(double x) const {
  const double s = classical_stress();
  if (x <= interface) return s / young_left * x;
  return s / young_left * interface + s / young_right * (x - interface);
}

namespace {
// hyp(x) * sinh(c/l) / sinh(L/l) with hyp = cosh (sign = +1) or sinh (sign = -1), for
// 0 <= x, c and x + c <= L. Written with exponentials of non-positive arguments only,
// so that l << L neither overflows nor loses the tiny boundary-layer values.
double hyp_ratio(double x, double c, double L, double l, double sign) {
  const double num = std::exp((x + c - L) / l) - std::exp((x - c - L) / l) +
                     sign * (std::exp((-x + c - L) / l) - std::exp((-x - c - L) / l));
  return 0.5 * num / (1.0 - std::exp(-2.0 * L / l));
}
}  // namespace

double BimaterialBar::gradient_strain(double x, double l) const {
  if (l <= 0.0) return classical_strain(x);
  const double s = classical_stress();
  const double e1 = s / young_left, e2 = s / young_right, b = length - interface;
  if (x <= interface) return e1 - (e1 - e2) * hyp_ratio(x, b, length, l, +1.0);
  return e2 + (e1 - e2) * hyp_ratio(length - x, interface, length, l, +1.0);
}

double BimaterialBar::gradient_displacement(double x, double l) const {
  if (l <= 0.0) return classical_displacement(x);
  const double s = classical_stress();
  const double e1 = s / young_left, e2 = s / young_right, b = length - interface;
  if (x <= interface) return e1 * x - l * (e1 - e2) * hyp_ratio(x, b, length, l, -1.0);
  return end_displacement - e2 * (length - x) - l * (e1 - e2) * hyp_ratio(length - x, interface, length, l, -1.0);
}

}  // namespace gradmpm::analytic
