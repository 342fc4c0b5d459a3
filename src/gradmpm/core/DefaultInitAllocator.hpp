#pragma once
// std::allocator whose value-less construct() default-initialises, so a vector of
// trivially constructible elements made with a size is not zeroed (the points' material
// responses of a load step: 40 MB at 2e5 points, written before they are read).
#include <memory>
#include <new>
#include <type_traits>
#include <utility>

namespace gradmpm {

template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  using std::allocator<T>::allocator;
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

}  // namespace gradmpm
