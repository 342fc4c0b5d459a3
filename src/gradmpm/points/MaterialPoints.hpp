#pragma once
// Material points carry all state of the analysis (paper, section 1). Stored as a
// structure of arrays so that hot loops stream through contiguous memory.
#include <vector>

#include "gradmpm/core/Types.hpp"

namespace gradmpm {

template <int dim>
struct MaterialPoints {
  std::vector<Vec<dim>> position;  ///< current position x_p
  std::vector<double> volume;      ///< current volume V_p (integration weight)
  std::vector<int> material;       ///< index into the case's material list

  int size() const { return static_cast<int>(position.size()); }

  void add(const Vec<dim>& x, double v, int mat) {
    position.push_back(x);
    volume.push_back(v);
    material.push_back(mat);
  }
};

}  // namespace gradmpm
