#include "gradmpm/materials/MaterialRegistry.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "gradmpm/io/CaseFile.hpp"

namespace gradmpm {

MaterialInfo linear_elastic_info();  // materials/LinearElastic.cpp
MaterialInfo hencky_info();          // materials/Hencky.cpp
MaterialInfo von_mises_info();       // materials/VonMises.cpp
MaterialInfo drucker_prager_info();  // materials/DruckerPrager.cpp
MaterialInfo mohr_coulomb_info();    // materials/MohrCoulomb.cpp
MaterialInfo modified_cam_clay_info();  // materials/ModifiedCamClay.cpp

void register_builtins(MaterialRegistry& registry) {
  // One entry per law, in the order the docs list them.
  for (MaterialInfo (*info)() :
       {hencky_info, linear_elastic_info, von_mises_info, drucker_prager_info, mohr_coulomb_info,
        modified_cam_clay_info})
    registry.add(info());
}

// A table of keys, one per line or two (laid out by hand).
// clang-format off
std::vector<KeySpec> isotropic_elasticity_keys() {
  return {
      {.name = "young", .type = KeyType::Number, .min = 0.0, .min_open = true, .allowed = "a Young's modulus > 0",
       .doc = "Young's modulus E"},
      {.name = "poisson", .type = KeyType::Number, .default_value = 0.0, .min = -1.0, .max = 0.5, .min_open = true,
       .max_open = true, .allowed = "a Poisson's ratio in (-1, 0.5)", .doc = "Poisson's ratio nu"},
      {.name = "density", .type = KeyType::Number, .default_value = 0.0, .min = 0.0, .allowed = "a density >= 0",
       .doc = "reference mass density rho_0 (body force m_p g)"},
  };
}
// clang-format on

const KeySpec& LawKeys::spec(const std::string& name) const {
  for (const auto& k : self.keys)
    if (k.name == name) return k;
  throw std::logic_error(self.model + " declares no key " + name);
}

bool LawKeys::has(const std::string& name) const { return cf.has(prefix + "." + spec(name).name); }

void LawKeys::require(bool ok, const std::string& name, const std::string& expected) const {
  cf.require(ok, prefix + "." + name, expected);
}

ElasticSolid read_elastic_solid(const CaseFile& cf, const std::string& prefix, const MaterialInfo& self) {
  const LawKeys in{cf, prefix, self};
  return {IsotropicElasticity(in.number("young"), in.number("poisson")), in.number("density")};
}

}  // namespace gradmpm
