#include "gradmpm/io/CaseFile.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

namespace {
std::string show(const toml::node& n) {
  std::ostringstream os;
  if (const auto* s = n.as_string())
    os << '"' << s->get() << '"';
  else
    n.visit([&](const auto& v) { os << v; });
  std::string text = os.str();
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return text;
}

std::vector<std::string> split_key(const std::string& key) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    parts.push_back(key.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return parts;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}
}  // namespace

CaseFile CaseFile::load(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open case file ({})", file.string(), std::strerror(errno)));
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse(buffer.str(), file.string(), overrides);
}

CaseFile CaseFile::parse(std::string_view text, std::string name, const std::vector<std::string>& overrides) {
  toml::table table;
  try {
    table = toml::parse(text, std::string_view(name));
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(fmt::format("{}:{}:{}: invalid TOML: {}", name, b.line, b.column, e.description()));
  }
  CaseFile cf(std::move(table), std::move(name));
  for (const auto& o : overrides) cf.apply_override(o);
  return cf;
}

void CaseFile::apply_override(const std::string& assignment) {
  const std::size_t eq = assignment.find('=');
  const std::string key = assignment.substr(0, eq);
  const auto parts = split_key(key);
  bool valid = eq != std::string::npos && parts.size() >= 2;
  for (const auto& p : parts) valid = valid && !p.empty();
  if (!valid)
    throw InputError(fmt::format("--set '{}': expected section.key=value (e.g. bar.elements=160)", assignment));
  const std::string value = assignment.substr(eq + 1);

  // The value as TOML ("160", "2.5", "[1e3, 5e3]", "true", "\"e-RA\""), else a plain string.
  toml::table holder;
  try {
    holder = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    holder = toml::table{{"v", value}};
  }

  toml::table* t = &table_;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    toml::node* child = t->get(parts[i]);
    if (!child) child = &t->insert_or_assign(parts[i], toml::table{}).first->second;
    t = child->as_table();
    if (!t) throw InputError(fmt::format("--set '{}': '{}' is not a section in {}", assignment, parts[i], name_));
  }
  if (const toml::node* existing = t->get(parts.back()); existing && existing->is_table())
    throw InputError(fmt::format("--set '{}': '{}' is a section in {}, not a key", assignment, key, name_));
  t->insert_or_assign(parts.back(), std::move(*holder.get("v")));
  overridden_.insert(key);
}

bool CaseFile::has_section(std::string_view section) const {
  const toml::node* n = table_.get(section);
  return n && n->is_table();
}

void CaseFile::declare_section(const std::string& section, std::initializer_list<std::string> keys, bool required) {
  declared_[section] = std::vector<std::string>(keys);
  const toml::node* n = table_.get(section);
  if (n && !n->is_table())
    throw InputError(fmt::format("{}: {}: expected a section [{}], got a value", name_, section, section));
  if (required && !n)
    throw InputError(fmt::format("{}: missing section [{}] (keys: {})", name_, section, join(declared_[section])));
}

void CaseFile::reject_unknown() const {
  std::vector<std::string> sections;
  for (const auto& [s, keys] : declared_) sections.push_back("[" + s + "]");
  for (const auto& [k, node] : table_) {
    const std::string section(k.str());
    const auto it = declared_.find(section);
    if (it == declared_.end()) {
      if (node.is_table())
        throw InputError(fmt::format("{}: unknown section [{}] (expected {})", name_, section, join(sections)));
      throw InputError(fmt::format("{}: {}: unknown top-level key (expected the sections {})", name_, section, join(sections)));
    }
    for (const auto& [kk, v] : *node.as_table()) {
      const std::string key(kk.str());
      bool known = false;
      for (const auto& d : it->second) known = known || d == key;
      if (!known)
        throw InputError(fmt::format("{}: unknown key (valid keys in [{}]: {})", where(section + "." + key), section,
                                     join(it->second)));
    }
  }
}

std::string CaseFile::where(const std::string& key) const {
  if (overridden_.count(key)) return fmt::format("{}: {} (from --set)", name_, key);
  return fmt::format("{}: {}", name_, key);
}

const toml::node* CaseFile::find(const std::string& key) const {
  return table_.at_path(key).node();
}

void CaseFile::fail(const std::string& key, std::string_view expected) const {
  const toml::node* n = find(key);
  if (!n) throw InputError(fmt::format("{}: missing key; expected {}", where(key), expected));
  throw InputError(fmt::format("{}: expected {}, got {}", where(key), expected, show(*n)));
}

const toml::node& CaseFile::need(const std::string& key, std::string_view expected) const {
  const toml::node* n = find(key);
  if (!n) fail(key, expected);
  return *n;
}

double CaseFile::number(const std::string& key) const {
  const toml::node& n = need(key, "a number");
  const auto v = n.value<double>();  // integers convert
  if (!v || !(n.is_floating_point() || n.is_integer())) fail(key, "a number");
  if (!std::isfinite(*v)) fail(key, "a finite number");
  return *v;
}
double CaseFile::number_or(const std::string& key, double fallback) const {
  return find(key) ? number(key) : fallback;
}

long long CaseFile::integer(const std::string& key) const {
  const toml::node& n = need(key, "an integer");
  if (!n.is_integer()) fail(key, "an integer");
  return *n.value<long long>();
}
long long CaseFile::integer_or(const std::string& key, long long fallback) const {
  return find(key) ? integer(key) : fallback;
}

std::string CaseFile::string(const std::string& key) const {
  const toml::node& n = need(key, "a string");
  if (!n.is_string()) fail(key, "a string");
  return *n.value<std::string>();
}
std::string CaseFile::string_or(const std::string& key, const std::string& fallback) const {
  return find(key) ? string(key) : fallback;
}

bool CaseFile::boolean_or(const std::string& key, bool fallback) const {
  const toml::node* n = find(key);
  if (!n) return fallback;
  if (!n->is_boolean()) fail(key, "true or false");
  return *n->value<bool>();
}

std::vector<double> CaseFile::numbers(const std::string& key, std::size_t count) const {
  const std::string expected = fmt::format("an array of {} numbers", count);
  const toml::node& n = need(key, expected);
  const toml::array* a = n.as_array();
  if (!a || a->size() != count) fail(key, expected);
  std::vector<double> out;
  for (const auto& e : *a) {
    const auto v = e.value<double>();
    if (!v || !(e.is_floating_point() || e.is_integer()) || !std::isfinite(*v)) fail(key, expected);
    out.push_back(*v);
  }
  return out;
}

}  // namespace gradmpm
