#pragma once
// The Ru-Aifantis operator-split variants (Askes, Morata & Aifantis 2008):
// which classical field is smoothed by (1 - l^2 laplacian).
#include <optional>
#include <string_view>

namespace gradmpm {

enum class GradientVariant {
  None,  ///< classical elasticity only
  U_RA,  ///< u_g - l^2 u_g'' = u_c, Dirichlet data copied from the classical problem
  E_RA,  ///< eps_g - l^2 eps_g'' = eps_c, natural (zero normal gradient) boundaries
  S_RA,  ///< sig_g - l^2 sig_g'' = sig_c, natural boundaries
};

inline std::optional<GradientVariant> parse_gradient_variant(std::string_view s) {
  if (s == "none") return GradientVariant::None;
  if (s == "u-RA") return GradientVariant::U_RA;
  if (s == "e-RA") return GradientVariant::E_RA;
  if (s == "s-RA") return GradientVariant::S_RA;
  return std::nullopt;
}

inline std::string_view to_string(GradientVariant v) {
  switch (v) {
    case GradientVariant::U_RA:
      return "u-RA";
    case GradientVariant::E_RA:
      return "e-RA";
    case GradientVariant::S_RA:
      return "s-RA";
    default:
      return "none";
  }
}

}  // namespace gradmpm
