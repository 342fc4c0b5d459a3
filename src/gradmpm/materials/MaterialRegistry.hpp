#pragma once
// Constitutive laws by model name, as a [materials.NAME] section selects them
// (model = "..."). Each law declares its own keys (default, range, doc: io/Keys.hpp)
// and reads them; the case reader only looks the model up. Built-in laws are registered
// in MaterialRegistry.cpp, one line each; a test or an application may add more.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gradmpm/io/Keys.hpp"
#include "gradmpm/materials/Material.hpp"

namespace gradmpm {

struct MaterialInfo {
  std::string model;  ///< the value of `model`
  std::string doc;    ///< one line
  std::vector<KeySpec> keys;  ///< every key besides `model`
  /// Reads the law's keys from the section `prefix` ("materials.soil") and makes it.
  std::function<std::shared_ptr<const Material>(const CaseFile& cf, const std::string& prefix, const MaterialInfo& self)> make;
};

class MaterialRegistry {
 public:
  static MaterialRegistry& instance();
  void add(MaterialInfo info);  ///< adds or replaces by model name
  const MaterialInfo* find(const std::string& model) const;
  const std::vector<MaterialInfo>& all() const { return laws_; }
  std::string quoted_names() const;  ///< "\"hencky\", \"linear-elastic\", ..."

 private:
  std::vector<MaterialInfo> laws_;
};

/// young, poisson, density: the keys of isotropic elasticity every law so far has.
std::vector<KeySpec> isotropic_elasticity_keys();
struct ElasticSolid {
  IsotropicElasticity elasticity;
  double density = 0.0;
};
/// Reads young, poisson and density from `prefix` with `self`'s specs of them.
ElasticSolid read_elastic_solid(const CaseFile& cf, const std::string& prefix, const MaterialInfo& self);

}  // namespace gradmpm
