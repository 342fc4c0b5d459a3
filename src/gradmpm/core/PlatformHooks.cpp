#include "gradmpm/core/PlatformHooks.hpp"

namespace gradmpm {

PlatformHooks& platform_hooks() {
  static PlatformHooks hooks;
  return hooks;
}

}  // namespace gradmpm
