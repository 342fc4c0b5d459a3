#include "gradmpm/points/Generate.hpp"

#include <cmath>
#include <string>

namespace gradmpm {

GaussRule01::GaussRule01(int points) : n(points) {
  // Standard rules on [-1, 1], mapped to [0, 1] below.
  switch (points) {
    case 1:
      xi = {0.0};
      w = {2.0};
      break;
    case 2: {
      const double a = 1.0 / std::sqrt(3.0);
      xi = {-a, a};
      w = {1.0, 1.0};
      break;
    }
    case 3: {
      const double a = std::sqrt(0.6);
      xi = {-a, 0.0, a};
      w = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
      break;
    }
    case 4: {
      const double a = std::sqrt(3.0 / 7.0 - 2.0 / 7.0 * std::sqrt(6.0 / 5.0));
      const double b = std::sqrt(3.0 / 7.0 + 2.0 / 7.0 * std::sqrt(6.0 / 5.0));
      const double wa = (18.0 + std::sqrt(30.0)) / 36.0;
      const double wb = (18.0 - std::sqrt(30.0)) / 36.0;
      xi = {-b, -a, a, b};
      w = {wb, wa, wa, wb};
      break;
    }
    default:
      throw std::invalid_argument("Gauss rule with " + std::to_string(points) + " points is not available (1 to 4)");
  }
  for (int i = 0; i < n; ++i) {
    xi[i] = 0.5 * (xi[i] + 1.0);
    w[i] *= 0.5;
  }
}

}  // namespace gradmpm
