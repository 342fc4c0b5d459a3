#include "gradmpm/io/Keys.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "gradmpm/io/CaseFile.hpp"

namespace gradmpm {

namespace {
std::string number_text(double v) {
  if (v == static_cast<double>(static_cast<long long>(v)) && std::abs(v) < 1e15)
    return fmt::format("{}", static_cast<long long>(v));
  return fmt::format("{}", v);
}

std::string quoted(const std::vector<std::string>& v, const char* last_sep) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i)
    s += fmt::format("{}\"{}\"", i == 0 ? "" : (i + 1 == v.size() ? last_sep : ", "), v[i]);
  return s;
}

/// Table cells may not hold a bare '|'.
std::string cell(std::string s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}
}  // namespace

std::string KeySpec::type_name() const {
  static constexpr const char* plain[] = {"number", "integer", "string", "boolean"};
  return type == KeyType::Other ? type_text : plain[static_cast<int>(type)];
}

std::string KeySpec::default_name() const {
  if (!default_text.empty()) return default_text;
  if (!default_value) return "required";
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::string>)
          return fmt::format("`\"{}\"`", v);
        else if constexpr (std::is_same_v<T, bool>)
          return v ? "`true`" : "`false`";
        else
          return fmt::format("`{}`", v);
      },
      *default_value);
}

std::string KeySpec::expected() const {
  if (!allowed.empty()) return allowed;
  if (!choices.empty()) return (choices.size() == 1 ? "" : "one of ") + quoted(choices, ", ");
  const char* what = type == KeyType::Integer ? "an integer" : "a number";
  if (min && max) {
    if (type == KeyType::Integer) return fmt::format("{} from {} to {}", what, number_text(*min), number_text(*max));
    return fmt::format("{} in {}{}, {}{}", what, min_open ? "(" : "[", number_text(*min), number_text(*max),
                       max_open ? ")" : "]");
  }
  if (min) return fmt::format("{} {} {}", what, min_open ? ">" : ">=", number_text(*min));
  if (max) return fmt::format("{} {} {}", what, max_open ? "<" : "<=", number_text(*max));
  return type_name();
}

std::vector<std::string> SectionSpec::key_names() const {
  std::vector<std::string> names;
  for (const auto& k : keys) names.push_back(k.name);
  return names;
}

const KeySpec& SectionSpec::key(const std::string& key_name) const {
  for (const auto& k : keys)
    if (k.name == key_name) return k;
  throw std::logic_error("undeclared key " + name + "." + key_name);
}

std::string SectionSpec::heading() const {
  switch (kind) {
    case SectionKind::Array:
      return "[[" + name + "]]";
    case SectionKind::TableOfSections:
      return "[" + name + ".NAME]";
    default:
      return "[" + name + "]";
  }
}

namespace {
template <class T>
bool in_range(const KeySpec& s, T v) {
  if (s.min && (s.min_open ? !(v > *s.min) : !(v >= *s.min))) return false;
  if (s.max && (s.max_open ? !(v < *s.max) : !(v <= *s.max))) return false;
  return true;
}
template <class T>
T fallback(const KeySpec& s) {
  return std::get<T>(*s.default_value);
}
}  // namespace

double read_number(const CaseFile& cf, const std::string& prefix, const KeySpec& s) {
  const std::string key = prefix + "." + s.name;
  const double v = s.default_value ? cf.number_or(key, fallback<double>(s)) : cf.number(key);
  cf.require(in_range(s, v), key, s.expected());
  return v;
}

long long read_integer(const CaseFile& cf, const std::string& prefix, const KeySpec& s) {
  const std::string key = prefix + "." + s.name;
  const long long v = s.default_value ? cf.integer_or(key, fallback<long long>(s)) : cf.integer(key);
  cf.require(in_range(s, static_cast<double>(v)), key, s.expected());
  return v;
}

std::string read_string(const CaseFile& cf, const std::string& prefix, const KeySpec& s) {
  const std::string key = prefix + "." + s.name;
  const std::string v = s.default_value ? cf.string_or(key, fallback<std::string>(s)) : cf.string(key);
  bool ok = s.choices.empty();
  for (const auto& c : s.choices) ok = ok || c == v;
  cf.require(ok, key, s.expected());
  return v;
}

bool read_boolean(const CaseFile& cf, const std::string& prefix, const KeySpec& s) {
  const std::string key = prefix + "." + s.name;
  return cf.boolean_or(key, s.default_value ? fallback<bool>(s) : false);
}

std::string markdown_table(const SectionSpec& section) {
  std::string t = "| key | type | default | allowed | meaning |\n|---|---|---|---|---|\n";
  for (const auto& k : section.keys) {
    const std::string allowed =
        k.type == KeyType::Boolean || (k.type == KeyType::Other && k.allowed.empty()) ? "" : k.expected();
    t += fmt::format("| `{}` | {} | {} | {} | {} |\n", k.name, cell(k.type_name()), cell(k.default_name()),
                     cell(allowed), cell(k.doc));
  }
  return t;
}

}  // namespace gradmpm
