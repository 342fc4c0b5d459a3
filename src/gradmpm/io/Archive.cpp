#include "gradmpm/io/Archive.hpp"

#include <fmt/format.h>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

void Archive::missing(const std::string& name, const char* kind) const {
  throw InputError(
      fmt::format("{}: no {} '{}' (not a checkpoint of this kind of run, or damaged)", source_, kind, name));
}

namespace {
template <typename V>
const V& sized(const V& v, long long size, const std::string& source, const std::string& name) {
  if (size >= 0 && static_cast<long long>(v.size()) != size)
    throw InputError(fmt::format("{}: '{}' holds {} values, expected {}", source, name, v.size(), size));
  return v;
}
}  // namespace

const std::vector<double>& Archive::reals(const std::string& name, long long size) const {
  const auto it = reals_.find(name);
  if (it == reals_.end()) missing(name, "real array");
  return sized(it->second, size, source_, name);
}

const std::vector<long long>& Archive::integers(const std::string& name, long long size) const {
  const auto it = integers_.find(name);
  if (it == integers_.end()) missing(name, "integer array");
  return sized(it->second, size, source_, name);
}

const std::string& Archive::text(const std::string& name) const {
  const auto it = texts_.find(name);
  if (it == texts_.end()) missing(name, "text");
  return it->second;
}

}  // namespace gradmpm
