#pragma once
// Constitutive laws by model name, as a [materials.NAME] section selects them
// (model = "..."). Each law declares its own keys (default, range, doc: io/Keys.hpp)
// and reads them; the case reader only looks the model up. Built-in laws are registered
// in MaterialRegistry.cpp, one line each; a test or an application may add more.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gradmpm/core/Registry.hpp"
#include "gradmpm/io/Keys.hpp"
#include "gradmpm/materials/Material.hpp"

namespace gradmpm {

struct MaterialInfo {
  std::string model;          ///< the value of `model`
  std::string doc;            ///< one line
  std::vector<KeySpec> keys;  ///< every key besides `model`
  /// Reads the law's keys from the section `prefix` ("materials.soil") and makes it.
  std::function<std::shared_ptr<const Material>(const CaseFile& cf, const std::string& prefix,
                                                const MaterialInfo& self)>
      make;
};

/// young, poisson, density: the keys of isotropic elasticity every law so far has.
std::vector<KeySpec> isotropic_elasticity_keys();
struct ElasticSolid {
  IsotropicElasticity elasticity;
  double density = 0.0;
};
/// Reads young, poisson and density from `prefix` with `self`'s specs of them.
ElasticSolid read_elastic_solid(const CaseFile& cf, const std::string& prefix, const MaterialInfo& self);

/// A law's keys read by name, with the law's own specs (defaults, ranges, messages).
struct LawKeys {
  const CaseFile& cf;
  const std::string& prefix;  ///< "materials.soil"
  const MaterialInfo& self;
  const KeySpec& spec(const std::string& name) const;
  double number(const std::string& name) const { return read_number(cf, prefix, spec(name)); }
  std::string string(const std::string& name) const { return read_string(cf, prefix, spec(name)); }
  /// Whether the case gives the (optional, default-less) key.
  bool has(const std::string& name) const;
  /// InputError on `prefix.name` unless ok.
  void require(bool ok, const std::string& name, const std::string& expected) const;
};

class MaterialRegistry : public Registry<MaterialRegistry, MaterialInfo, &MaterialInfo::model> {
 public:
  std::string quoted_names() const {  ///< "\"hencky\" or \"linear-elastic\""
    return Registry::quoted_names([](const MaterialInfo&) { return true; });
  }
};

/// The built-in laws (MaterialRegistry.cpp: one line each).
void register_builtins(MaterialRegistry& registry);

/// The MaterialInfo of a law whose keys are those of isotropic elasticity and whose
/// constructor is Law(young, poisson, density).
template <class Law>
MaterialInfo elastic_law_info(std::string model, std::string doc) {
  return {
      std::move(model), std::move(doc), isotropic_elasticity_keys(),
      [](const CaseFile& cf, const std::string& prefix, const MaterialInfo& self) -> std::shared_ptr<const Material> {
        const ElasticSolid s = read_elastic_solid(cf, prefix, self);
        return std::make_shared<Law>(s.elasticity.young, s.elasticity.poisson, s.density);
      }};
}

}  // namespace gradmpm
