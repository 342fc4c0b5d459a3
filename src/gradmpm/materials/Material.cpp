#include "gradmpm/materials/Material.hpp"

namespace gradmpm {

int Material::state_size() const {
  int n = 0;
  for (const auto& v : state_variables()) n += v.size();
  return n;
}

void Material::initial_state(double* state) const {
  for (const auto& v : state_variables())
    for (int c = 0; c < v.size(); ++c) *state++ = v.initial;
}

}  // namespace gradmpm
