#pragma once
// A list of named entries (materials, linear solvers) that built-in registration fills
// once and tests or applications may extend: the one pattern behind MaterialRegistry
// and LinearSolverRegistry. Entries are found by Info::*name_of (the case-file value).
#include <fmt/format.h>

#include <string>
#include <utility>
#include <vector>

namespace gradmpm {

/// `Derived` is the registry class; a free function register_builtins(Derived&), found
/// by argument-dependent lookup, fills it the first time instance() is called.
template <class Derived, class Info, std::string Info::*name_of>
class Registry {
 public:
  /// The registry holding the built-in entries (and any added at run time).
  static Derived& instance() {
    static Derived registry = [] {
      Derived r;
      register_builtins(r);
      return r;
    }();
    return registry;
  }

  /// Adds an entry, or replaces the one of the same name.
  void add(Info info) {
    for (auto& e : entries_)
      if (e.*name_of == info.*name_of) {
        e = std::move(info);
        return;
      }
    entries_.push_back(std::move(info));
  }
  /// null when no entry has that name.
  const Info* find(const std::string& name) const {
    for (const auto& e : entries_)
      if (e.*name_of == name) return &e;
    return nullptr;
  }
  const std::vector<Info>& all() const { return entries_; }
  /// "\"a\", \"b\" or \"c\"" (or ", " before the last with last_sep = ", "), of the
  /// entries for which keep(entry) holds.
  template <class Keep>
  std::string quoted_names(Keep&& keep, const char* last_sep = " or ") const {
    std::vector<std::string> names;
    for (const auto& e : entries_)
      if (keep(e)) names.push_back(e.*name_of);
    std::string s;
    for (std::size_t i = 0; i < names.size(); ++i)
      s += fmt::format("{}\"{}\"", i == 0 ? "" : (i + 1 == names.size() ? last_sep : ", "), names[i]);
    return s;
  }

 private:
  std::vector<Info> entries_;
};

}  // namespace gradmpm
