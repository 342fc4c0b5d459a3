#include "gradmpm/io/CaseFile.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <type_traits>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

namespace {
/// Text for a one-line message: control characters escaped (\n, \t, \xNN).
std::string printable(std::string_view text) {
  // A message echoes at most 200 characters of a key or an assignment (a 100,000-character
  // key is a pasted mistake, not something to print whole).
  constexpr std::size_t kShown = 200;
  const bool cut = text.size() > kShown;
  if (cut) text = text.substr(0, kShown);
  std::string out;
  for (const char c : text) {
    if (c == '\n')
      out += "\\n";
    else if (c == '\t')
      out += "\\t";
    else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
    else
      out += c;
  }
  return cut ? out + "..." : out;
}

/// A value as one line: toml++ prints some arrays over several lines, which a message
/// folds back (runs of whitespace with a newline become one space).
std::string show(const toml::node& n) {
  std::ostringstream os;
  if (const auto* s = n.as_string())
    os << '"' << s->get() << '"';
  else
    n.visit([&](const auto& v) { os << v; });
  std::string text;
  if (n.is_string()) {
    text = printable(os.str());
  } else {
    const std::string raw = os.str();
    for (std::size_t i = 0; i < raw.size(); ++i) {
      if (raw[i] == '\n' || raw[i] == '\r') {
        while (i + 1 < raw.size() && std::isspace(static_cast<unsigned char>(raw[i + 1]))) ++i;
        if (!text.empty() && text.back() != ' ') text += ' ';
        continue;
      }
      text += raw[i];
    }
    text = printable(text);
  }
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return text;
}

std::string trimmed(std::string_view s) {
  const auto first = s.find_first_not_of(" \t"), last = s.find_last_not_of(" \t");
  return first == std::string_view::npos ? std::string() : std::string(s.substr(first, last - first + 1));
}

/// The parts of a dotted key, each trimmed of spaces and, as TOML's dotted keys allow, of
/// the double quotes around it (materials."soil".young is materials.soil.young).
std::vector<std::string> split_key(const std::string& key) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    std::string part = trimmed(std::string_view(key).substr(start, dot == std::string::npos ? dot : dot - start));
    if (part.size() >= 2 && part.front() == '"' && part.back() == '"') part = part.substr(1, part.size() - 2);
    parts.push_back(part);
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return parts;
}

/// The key path of its parts: a.b.c.
std::string join_key(const std::vector<std::string>& parts) {
  std::string key;
  for (const auto& p : parts) key += (key.empty() ? "" : ".") + p;
  return key;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}
}  // namespace

CaseFile CaseFile::load(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    throw InputError(
        fmt::format("{}: is a folder, not a case file (expected a .toml file, see examples/)", file.string()));
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
  // One line: TOML would read "80\nsplit = 0.9" as the value 80 and drop the rest.
  if (assignment.find_first_of("\n\r") != std::string::npos)
    throw InputError(
        fmt::format("--set '{}': expected one line section.key=value (it holds a line break)", printable(assignment)));
  const std::size_t eq = assignment.find('=');
  const auto parts = split_key(assignment.substr(0, eq));
  bool valid = eq != std::string::npos && parts.size() >= 2;
  for (const auto& p : parts) valid = valid && !p.empty();
  if (!valid)
    throw InputError(
        fmt::format("--set '{}': expected section.key=value (e.g. bar.elements=160)", printable(assignment)));
  const std::string key = join_key(parts);
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
    // "name[k]" addresses entry k of an array of tables ([[name]]).
    std::string part = parts[i];
    long index = -1;
    if (const auto lb = part.find('['); lb != std::string::npos && part.back() == ']') {
      const std::string digits = part.substr(lb + 1, part.size() - lb - 2);
      if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos)
        throw InputError(fmt::format("--set '{}': '{}' is not name[index]", printable(assignment), printable(part)));
      // No array of tables holds a billion entries; longer digit strings would overflow stol.
      if (digits.size() > 9)
        throw InputError(fmt::format("--set '{}': {} has no entry [{}] in {}", printable(assignment),
                                     printable(part.substr(0, lb)), digits, name_));
      index = std::stol(digits);
      part = part.substr(0, lb);
    }
    toml::node* child = t->get(part);
    if (index >= 0) {
      toml::array* a = child ? child->as_array() : nullptr;
      if (!a || index >= static_cast<long>(a->size()) || !(*a)[static_cast<std::size_t>(index)].is_table())
        throw InputError(fmt::format("--set '{}': {} has no entry [{}] in {}", printable(assignment), printable(part),
                                     index, name_));
      t = (*a)[static_cast<std::size_t>(index)].as_table();
      continue;
    }
    if (!child) child = &t->insert_or_assign(part, toml::table{}).first->second;
    t = child->as_table();
    if (!t)
      throw InputError(
          fmt::format("--set '{}': '{}' is not a section in {}", printable(assignment), printable(part), name_));
  }
  if (const toml::node* existing = t->get(parts.back()); existing && existing->is_table())
    throw InputError(
        fmt::format("--set '{}': '{}' is a section in {}, not a key", printable(assignment), printable(key), name_));
  t->insert_or_assign(parts.back(), std::move(*holder.get("v")));
  overridden_.insert(key);
}

bool CaseFile::has_section(std::string_view section) const {
  const toml::node* n = table_.get(section);
  return n && n->is_table();
}

void CaseFile::declare_section(const std::string& section, const std::vector<std::string>& keys, bool required) {
  declared_[section] = {Kind::Section, keys};
  const toml::node* n = table_.get(section);
  if (n && !n->is_table())
    throw InputError(fmt::format("{}: {}: expected a section [{}], got a value", name_, section, section));
  if (required && !n)
    throw InputError(fmt::format("{}: missing section [{}] (keys: {})", name_, section, join(declared_[section].keys)));
}

void CaseFile::declare_array(const std::string& name, const std::vector<std::string>& keys) {
  declared_[name] = {Kind::Array, keys};
  const toml::node* n = table_.get(name);
  if (n && !n->is_array_of_tables())
    throw InputError(fmt::format("{}: {}: expected an array of tables [[{}]]", name_, name, name));
}

void CaseFile::declare_table_of_sections(const std::string& name, const std::vector<std::string>& keys) {
  declared_[name] = {Kind::TableOfSections, keys};
  const toml::node* n = table_.get(name);
  if (!n) return;
  if (!n->is_table()) throw InputError(fmt::format("{}: {}: expected sections [{}.NAME]", name_, name, name));
  for (const auto& [k, v] : *n->as_table())
    if (!v.is_table())
      throw InputError(
          fmt::format("{}: {}.{}: expected a section [{}.{}], got a value", name_, name, k.str(), name, k.str()));
}

void CaseFile::declare(const SectionSpec& spec) {
  switch (spec.kind) {
    case SectionKind::Section:
      return declare_section(spec.name, spec.key_names(), spec.required);
    case SectionKind::Array:
      return declare_array(spec.name, spec.key_names());
    case SectionKind::TableOfSections:
      return declare_table_of_sections(spec.name, spec.key_names());
  }
}

void CaseFile::check_section_keys(const std::string& section, const std::vector<std::string>& keys,
                                  const std::string& whose) const {
  if (const toml::node* n = find(section); n && n->is_table()) check_keys(*n->as_table(), section, keys, whose);
}

std::size_t CaseFile::array_size(const std::string& name) const {
  const toml::node* n = table_.get(name);
  return n && n->is_array() ? n->as_array()->size() : 0;
}

std::vector<std::string> CaseFile::subsections(const std::string& name) const {
  std::vector<std::string> out;
  if (const toml::node* n = table_.get(name); n && n->is_table())
    for (const auto& [k, v] : *n->as_table()) out.emplace_back(k.str());
  return out;
}

void CaseFile::check_keys(const toml::table& t, const std::string& prefix, const std::vector<std::string>& keys,
                          const std::string& where_desc) const {
  for (const auto& [kk, v] : t) {
    const std::string key(kk.str());
    bool known = false;
    for (const auto& d : keys) known = known || d == key;
    if (!known)
      throw InputError(
          fmt::format("{}: unknown key (valid keys in {}: {})", where(prefix + "." + key), where_desc, join(keys)));
  }
}

void CaseFile::reject_unknown() const {
  std::vector<std::string> sections;
  for (const auto& [s, d] : declared_) sections.push_back(d.kind == Kind::Array ? "[[" + s + "]]" : "[" + s + "]");
  for (const auto& [k, node] : table_) {
    const std::string section(k.str());
    const auto it = declared_.find(section);
    if (it == declared_.end()) {
      if (node.is_table() || node.is_array_of_tables())
        throw InputError(
            fmt::format("{}: unknown section [{}] (expected {})", name_, printable(section), join(sections)));
      throw InputError(fmt::format("{}: {}: unknown top-level key (expected the sections {})", name_,
                                   printable(section), join(sections)));
    }
    const Declared& d = it->second;
    if (d.kind == Kind::Section) {
      check_keys(*node.as_table(), section, d.keys, "[" + section + "]");
    } else if (d.kind == Kind::Array) {
      const toml::array& a = *node.as_array();
      for (std::size_t i = 0; i < a.size(); ++i)
        check_keys(*a[i].as_table(), fmt::format("{}[{}]", section, i), d.keys, "[[" + section + "]]");
    } else {
      for (const auto& [sub, t] : *node.as_table())
        check_keys(*t.as_table(), section + "." + std::string(sub.str()), d.keys,
                   "[" + section + "." + std::string(sub.str()) + "]");
    }
  }
}

std::string CaseFile::where(const std::string& key) const {
  if (overridden_.count(key)) return fmt::format("{}: {} (from --set)", name_, printable(key));
  return fmt::format("{}: {}", name_, printable(key));
}

const toml::node* CaseFile::find(const std::string& key) const { return table_.at_path(key).node(); }

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
double CaseFile::number_or(const std::string& key, double fallback) const { return find(key) ? number(key) : fallback; }

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

std::vector<double> CaseFile::number_list(const std::string& key) const {
  const toml::node& n = need(key, "an array of numbers");
  const toml::array* a = n.as_array();
  if (!a || a->empty()) fail(key, "a non-empty array of numbers");
  return numbers(key, a->size());
}

std::vector<std::vector<double>> CaseFile::vector_list(const std::string& key, std::size_t count) const {
  const std::string expected = fmt::format("an array of [{}] coordinate arrays", count);
  const toml::node& n = need(key, expected);
  const toml::array* a = n.as_array();
  if (!a || a->empty()) fail(key, expected);
  std::vector<std::vector<double>> out;
  for (const auto& e : *a) {
    const toml::array* v = e.as_array();
    if (!v || v->size() != count) fail(key, expected);
    out.emplace_back();
    for (const auto& x : *v) {
      const auto d = x.value<double>();
      if (!d || !(x.is_integer() || x.is_floating_point()) || !std::isfinite(*d)) fail(key, expected);
      out.back().push_back(*d);
    }
  }
  return out;
}

std::vector<long long> CaseFile::integer_list(const std::string& key) const {
  const toml::node& n = need(key, "an array of integers");
  const toml::array* a = n.as_array();
  if (!a) fail(key, "an array of integers");
  std::vector<long long> out;
  for (const auto& e : *a) {
    if (!e.is_integer()) fail(key, "an array of integers");
    out.push_back(*e.value<long long>());
  }
  return out;
}

std::vector<std::string> CaseFile::string_list(const std::string& key) const {
  const toml::node& n = need(key, "an array of strings");
  const toml::array* a = n.as_array();
  if (!a) fail(key, "an array of strings");
  std::vector<std::string> out;
  for (const auto& e : *a) {
    if (!e.is_string()) fail(key, "an array of strings");
    out.push_back(*e.value<std::string>());
  }
  return out;
}

namespace {
/// A value as text in which numbers are the values they are (1, 1.0 and 1e0 read alike:
/// as the shortest text of the double) and arrays list their values so.
std::string canonical_value(const toml::node& n) {
  if (const auto* i = n.as_integer()) return fmt::format("{}", static_cast<double>(i->get()));
  if (const auto* d = n.as_floating_point()) return fmt::format("{}", d->get());
  if (const toml::array* a = n.as_array()) {
    std::string text = "[";
    for (std::size_t k = 0; k < a->size(); ++k) text += (k ? ", " : "") + canonical_value(*a->get(k));
    return text + "]";
  }
  std::ostringstream value;
  n.visit([&](const auto& x) { value << x; });
  return value.str();
}

/// The declared default as canonical_value writes a value.
std::string canonical_default(const KeySpec& spec) {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::string>) return canonical_value(toml::value<std::string>(v));
        else if constexpr (std::is_same_v<T, bool>) return v ? "true" : "false";
        else return fmt::format("{}", static_cast<double>(v));
      },
      *spec.default_value);
}

/// (key, value) for every value under `n` (arrays of tables by index: "bodies[0].min").
void flatten(const toml::node& n, const std::string& path, std::vector<std::pair<std::string, std::string>>& lines) {
  if (const toml::table* t = n.as_table()) {
    for (auto&& [k, v] : *t) flatten(v, path.empty() ? std::string(k.str()) : path + "." + std::string(k.str()), lines);
  } else if (const toml::array* a = n.as_array(); a && !a->empty() && a->is_array_of_tables()) {
    for (std::size_t i = 0; i < a->size(); ++i) flatten(*a->get(i), fmt::format("{}[{}]", path, i), lines);
  } else {
    lines.emplace_back(path, canonical_value(n));
  }
}
}  // namespace

std::string CaseFile::canonical_text(const std::function<const KeySpec*(const std::string& key)>& spec_of) const {
  std::vector<std::pair<std::string, std::string>> values;
  flatten(table_, "", values);
  std::vector<std::string> lines;
  for (const auto& [key, value] : values) {
    const KeySpec* spec = spec_of ? spec_of(key) : nullptr;
    if (spec && spec->default_value && canonical_default(*spec) == value) continue;
    lines.push_back(key + " = " + value);
  }
  std::sort(lines.begin(), lines.end());
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  return text;
}

}  // namespace gradmpm
