#pragma once
// The basis a case selects: standard MPM, uGIMP (domains keep their initial size) or
// cpGIMP (domains follow the deformation: l_p = l_p0 |F e_d| per direction).
#include <optional>
#include <string_view>

namespace gradmpm {

enum class BasisKind { MPM, UGIMP, CPGIMP };

inline std::optional<BasisKind> parse_basis(std::string_view s) {
  if (s == "mpm") return BasisKind::MPM;
  if (s == "gimp" || s == "ugimp") return BasisKind::UGIMP;
  if (s == "cpgimp") return BasisKind::CPGIMP;
  return std::nullopt;
}

inline std::string_view to_string(BasisKind b) {
  return b == BasisKind::MPM ? "mpm" : (b == BasisKind::UGIMP ? "ugimp" : "cpgimp");
}

}  // namespace gradmpm
