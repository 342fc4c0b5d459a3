#pragma once
// The nodes a material point talks to, with their shape-function values N and
// gradients dN/dx at the point. Fixed capacity (3^dim covers GIMP's support), so
// evaluating a basis never allocates.
#include <array>

#include "gradmpm/core/Types.hpp"

namespace gradmpm {

template <int dim>
struct Stencil {
  static constexpr int capacity = ipow(3, dim);
  int count = 0;
  std::array<int, capacity> node{};
  std::array<double, capacity> N{};
  std::array<Vec<dim>, capacity> dN{};
};

}  // namespace gradmpm
