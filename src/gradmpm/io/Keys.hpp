#pragma once
// Case-file keys declared once: name, type, default, allowed range and a one-line doc.
// The readers take their defaults and checks from here, CaseFile takes the list of
// valid keys from here, and `gradmpm keys --markdown` renders docs/case-files.md's
// tables from here (tests/test_keys.cpp fails when the checked-in file is stale).
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace gradmpm {

class CaseFile;

enum class KeyType { Number, Integer, String, Boolean, Other };

struct KeySpec {
  std::string name;  ///< within its section, e.g. "tolerance"
  KeyType type = KeyType::Other;
  std::string type_text;  ///< for the docs when the type is not a plain one, e.g. "[dim numbers]"
  /// The default; none means required (or, with default_text, optional without a value).
  std::optional<std::variant<double, long long, std::string, bool>> default_value = std::nullopt;
  std::string default_text;  ///< for the docs when the default is not a value ("zero", "none", ...)
  std::optional<double> min = std::nullopt, max = std::nullopt;  ///< numbers and integers
  bool min_open = false, max_open = false;                       ///< > instead of >=, < instead of <=
  std::vector<std::string> choices = {};                         ///< strings
  std::string allowed;  ///< what is expected, as error messages and the docs say it
  std::string doc;      ///< one line: what the key means

  bool required() const { return !default_value && default_text.empty(); }
  std::string type_name() const;
  std::string default_name() const;
  /// `allowed`, or the text the range or choices give.
  std::string expected() const;
};

enum class SectionKind { Section, Array, TableOfSections };

struct SectionSpec {
  std::string name;  ///< "nonlinear_solver", "bodies", "materials"
  SectionKind kind = SectionKind::Section;
  bool required = false;
  std::string doc;
  std::vector<KeySpec> keys;

  std::vector<std::string> key_names() const;
  const KeySpec& key(const std::string& name) const;  ///< throws std::logic_error if undeclared
  /// "[name]", "[[name]]" or "[name.NAME]"
  std::string heading() const;
};

/// Typed reads of `prefix.spec.name` (prefix: "nonlinear_solver", "bodies[2]", ...):
/// the default when absent, an InputError naming the key when required and absent, of
/// the wrong type, or outside the range or choices.
double read_number(const CaseFile& cf, const std::string& prefix, const KeySpec& spec);
long long read_integer(const CaseFile& cf, const std::string& prefix, const KeySpec& spec);
std::string read_string(const CaseFile& cf, const std::string& prefix, const KeySpec& spec);
bool read_boolean(const CaseFile& cf, const std::string& prefix, const KeySpec& spec);

/// One markdown table of a section's keys (key, type, default, allowed, meaning).
std::string markdown_table(const SectionSpec& section);

}  // namespace gradmpm
