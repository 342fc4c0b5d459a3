#include "gradmpm/analytic/Column.hpp"

#include <cmath>

namespace gradmpm::analytic {

double Column::stretch(double Y) const {
  const double q = density * gravity * (height - Y);
  double lam = 1.0;  // Newton on f = E ln(lam) + q lam, increasing and concave: converges from 1
  for (int it = 0; it < 100; ++it) {
    const double f = young * std::log(lam) + q * lam;
    const double step = f / (young / lam + q);
    lam -= step;
    if (std::abs(step) < 1e-16 * lam) break;
  }
  return lam;
}

double Column::position(double Y) const {
  auto primitive = [](double lam) {
    const double L = std::log(lam);
    return L - 0.5 * L * L;
  };
  return young / (density * gravity) * (primitive(stretch(Y)) - primitive(stretch(0.0)));
}

double Column::position_cauchy_log_law(double Y) const {
  const double k = density * gravity / young;
  return (std::exp(-k * (height - Y)) - std::exp(-k * height)) / k;
}

}  // namespace gradmpm::analytic
