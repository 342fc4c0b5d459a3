#pragma once
// A case file (TOML) with command-line overrides and precise error messages.
//
// Every error is an InputError whose message names the file, the key and what was
// expected, e.g.  "bar.toml: bar.elements: expected an integer >= 1, got 0".
// Sections declare their keys up front, so a misspelt key is reported as unknown
// (with the list of valid keys) before anything else is read.
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "gradmpm/io/Keys.hpp"

namespace gradmpm {

class CaseFile {
 public:
  /// Reads `file` and applies overrides of the form "section.key=value" (the value is
  /// parsed as TOML, or taken as a plain string when it is not valid TOML).
  static CaseFile load(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});
  /// Same, from text in memory (`name` stands in for the file name in messages).
  static CaseFile parse(std::string_view text, std::string name, const std::vector<std::string>& overrides = {});

  const std::string& name() const { return name_; }
  /// The case as read, overrides applied: one sorted line "section.key = value" per value
  /// (comments and layout dropped; numbers as the values they are, so 0, 0.0 and 0e0 read
  /// alike). `spec_of` (optional) gives a key's declaration ("bodies[0].points_per_cell"):
  /// a key whose value is its declared default is dropped, so spelling out a default does
  /// not make another case. What a checkpoint records and a restart compares.
  std::string canonical_text(const std::function<const KeySpec*(const std::string& key)>& spec_of = {}) const;
  bool has_section(std::string_view section) const;
  /// Drops a top-level section, if present: the case without it (the classical run of a
  /// regularised case, where type = "none" with the section's other keys is refused).
  void remove_section(std::string_view section) { table_.erase(section); }

  /// Declares the keys a section may hold; `required` sections must be present.
  void declare_section(const std::string& section, const std::vector<std::string>& keys, bool required);
  /// Declares an array of tables ([[name]]) and the keys each entry may hold.
  void declare_array(const std::string& name, const std::vector<std::string>& keys);
  /// Declares a table of tables ([name.X] for any X) and the keys each may hold.
  void declare_table_of_sections(const std::string& name, const std::vector<std::string>& keys);
  /// Declares a section from its spec (io/Keys.hpp): the key names come from there.
  void declare(const SectionSpec& spec);
  /// Throws on a key of the section `section` ("materials.soil") not in `keys`; `whose`
  /// says whose keys they are in the message (e.g. "model \"hencky\"").
  void check_section_keys(const std::string& section, const std::vector<std::string>& keys,
                          const std::string& whose) const;
  /// Number of entries of an array of tables (0 when absent).
  std::size_t array_size(const std::string& name) const;
  /// Number of entries of the array at `key` ("bodies[0].holes"; 0 when absent or not an array).
  std::size_t list_size(const std::string& key) const {
    const toml::node* n = find(key);
    return n && n->is_array() ? n->as_array()->size() : 0;
  }
  /// Names of the sub-tables of a table of sections, in file order.
  std::vector<std::string> subsections(const std::string& name) const;
  bool has(const std::string& key) const { return find(key) != nullptr; }
  bool is_array(const std::string& key) const {
    const toml::node* n = find(key);
    return n && n->is_array();
  }
  /// Throws on any section or key that was not declared.
  void reject_unknown() const;

  // Typed access to "section.key". Integers are accepted where numbers are expected.
  double number(const std::string& key) const;
  double number_or(const std::string& key, double fallback) const;
  long long integer(const std::string& key) const;
  long long integer_or(const std::string& key, long long fallback) const;
  std::string string(const std::string& key) const;
  std::string string_or(const std::string& key, const std::string& fallback) const;
  bool boolean_or(const std::string& key, bool fallback) const;
  std::vector<double> numbers(const std::string& key, std::size_t count) const;
  /// An array of numbers of any length >= 1.
  std::vector<double> number_list(const std::string& key) const;
  /// An array of `count`-vectors, e.g. polygon = [[0, 0], [1, 0], [0, 1]].
  std::vector<std::vector<double>> vector_list(const std::string& key, std::size_t count) const;
  std::vector<long long> integer_list(const std::string& key) const;
  std::vector<std::string> string_list(const std::string& key) const;

  /// Throws InputError "<file>: <key>: expected <expected>, got <value as written>".
  [[noreturn]] void fail(const std::string& key, std::string_view expected) const;
  /// fail() unless `ok`.
  void require(bool ok, const std::string& key, std::string_view expected) const {
    if (!ok) fail(key, expected);
  }

 private:
  CaseFile(toml::table table, std::string name) : table_(std::move(table)), name_(std::move(name)) {}
  void apply_override(const std::string& assignment);
  const toml::node* find(const std::string& key) const;
  const toml::node& need(const std::string& key, std::string_view expected) const;
  std::string where(const std::string& key) const;

  toml::table table_;
  std::string name_;
  std::set<std::string> overridden_;
  enum class Kind { Section, Array, TableOfSections };
  struct Declared {
    Kind kind;
    std::vector<std::string> keys;
  };
  void check_keys(const toml::table& t, const std::string& prefix, const std::vector<std::string>& keys,
                  const std::string& where_desc) const;
  std::map<std::string, Declared> declared_;  // section -> keys
};

}  // namespace gradmpm
