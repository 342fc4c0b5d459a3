#pragma once
// Shared set-up of the bi-material bar tests: the paper's case (L = 10, split 0.5,
// E = [1000, 5000], delta = 0.1, l = 2) and its closed form.
#include <cmath>

#include "gradmpm/analytic/BimaterialBar.hpp"
#include "gradmpm/app/BarProblem.hpp"

namespace gradmpm::test {

inline BarConfig paper_bar(GradientVariant v, int elements, double l = 2.0) {
  BarConfig c;
  c.length = 10.0;
  c.split = 0.5;
  c.young_left = 1000.0;
  c.young_right = 5000.0;
  c.end_displacement = 0.1;
  c.elements = elements;
  c.variant = v;
  c.length_scale = l;
  return c;
}

inline analytic::BimaterialBar closed_form(const BarConfig& c) {
  return {c.length, c.split * c.length, c.young_left, c.young_right, c.end_displacement};
}

/// Index of the grid node at x (x must be a node).
inline int node_at(const BarConfig& c, double x) { return static_cast<int>(std::lround(x / (c.length / c.elements))); }

}  // namespace gradmpm::test
