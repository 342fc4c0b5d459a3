#include "gradmpm/app/KeysDoc.hpp"

#include <fmt/format.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "gradmpm/app/CaseKeys.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/io/StagedOutputs.hpp"
#include "gradmpm/materials/MaterialRegistry.hpp"

namespace gradmpm {

namespace {
std::string section_markdown(const SectionSpec& s) {
  std::string out = fmt::format("#### `{}` ({}): {}\n\n", s.heading(), s.required ? "required" : "optional", s.doc);
  if (s.kind != SectionKind::TableOfSections) return out + markdown_table(s) + "\n";
  // [materials.NAME]: `model`, then the keys of each registered law.
  SectionSpec model = s;
  model.keys = {s.key("model")};
  out += markdown_table(model) + "\n";
  for (const auto& law : MaterialRegistry::instance().all()) {
    SectionSpec keys{s.name, s.kind, false, law.doc, law.keys};
    out += fmt::format("`model = \"{}\"`: {}\n\n{}\n", law.model, law.doc, markdown_table(keys));
  }
  return out;
}
}  // namespace

std::vector<std::string> key_doc_kinds() { return {"bar", "bar-mpm", "mpm"}; }

std::string keys_markdown(const std::string& kind) {
  std::vector<const SectionSpec*> sections;
  if (kind == "bar")
    sections = {&bar_section(), &bar_gradient_section(), &linear_solver_section(), &bar_output_section()};
  else if (kind == "bar-mpm")
    sections = {&bar_mpm_section(), &bar_mpm_gradient_section()};
  else if (kind == "mpm")
    for (const auto& s : mpm_sections()) sections.push_back(&s);
  else
    throw InputError(fmt::format("gradmpm keys: unknown kind \"{}\" (expected bar, bar-mpm or mpm)", kind));
  std::string out;
  for (const auto* s : sections) out += section_markdown(*s);
  return out;
}

std::string with_generated_keys(const std::string& doc) {
  const std::string open = "<!-- keys ", close = "<!-- /keys -->";
  std::string out;
  std::size_t pos = 0;
  while (true) {
    const std::size_t m = doc.find(open, pos);
    if (m == std::string::npos) break;
    const std::size_t end_of_marker = doc.find("-->", m);
    const std::size_t c = doc.find(close, m);
    if (end_of_marker == std::string::npos || c == std::string::npos)
      throw std::runtime_error("unclosed <!-- keys KIND --> marker");
    std::string kind = doc.substr(m + open.size(), end_of_marker - m - open.size());
    while (!kind.empty() && kind.back() == ' ') kind.pop_back();
    out += doc.substr(pos, end_of_marker + 3 - pos) + "\n\n" + keys_markdown(kind);
    pos = c;
  }
  return out + doc.substr(pos);
}

void update_generated_keys(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open", path.string()));
  std::stringstream text;
  text << in.rdbuf();
  std::string updated;
  try {
    updated = with_generated_keys(text.str());
  } catch (const std::runtime_error& e) {
    throw InputError(fmt::format("{}: {}", path.string(), e.what()));
  }
  StagedOutputs out(path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path());
  out.write_text(path.filename().string(), updated);
  out.commit();
}

}  // namespace gradmpm
