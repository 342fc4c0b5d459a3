#include "gradmpm/geometry/GmshMesh.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

namespace {

/// The file's text read as whitespace-separated tokens, with the line of each (for
/// messages). Numbers are parsed where they are read, so 1e6 elements stay a few seconds.
class Tokens {
 public:
  Tokens(std::string text, std::string file) : text_(std::move(text)), file_(std::move(file)) {}

  bool done() {
    skip();
    return at_ >= text_.size();
  }
  std::string word() {
    skip();
    const std::size_t start = at_;
    while (at_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
    if (start == at_) fail("the file ends inside a section");
    return text_.substr(start, at_ - start);
  }
  long long integer(const char* what) {
    skip();
    const char* begin = text_.c_str() + at_;
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(begin, &end, 10);
    if (end == begin || errno != 0 || (*end != '\0' && !std::isspace(static_cast<unsigned char>(*end))))
      fail(fmt::format("expected an integer ({}), got \"{}\"", what, peek()));
    at_ += static_cast<std::size_t>(end - begin);
    return v;
  }
  double real(const char* what) {
    skip();
    const char* begin = text_.c_str() + at_;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin || (*end != '\0' && !std::isspace(static_cast<unsigned char>(*end))))
      fail(fmt::format("expected a number ({}), got \"{}\"", what, peek()));
    at_ += static_cast<std::size_t>(end - begin);
    return v;
  }
  /// The rest of the line (a physical name with its quotes).
  std::string rest_of_line() {
    while (at_ < text_.size() && (text_[at_] == ' ' || text_[at_] == '\t')) ++at_;
    const std::size_t start = at_;
    while (at_ < text_.size() && text_[at_] != '\n' && text_[at_] != '\r') ++at_;
    return text_.substr(start, at_ - start);
  }
  /// Skips to the line after `end` ("$EndComments").
  void skip_past(const std::string& end) {
    const std::size_t found = text_.find(end, at_);
    if (found == std::string::npos) fail(fmt::format("no {} after its section", end));
    at_ = found + end.size();
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(fmt::format("{}:{}: {}", file_, line(), what));
  }

 private:
  void skip() {
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
  }
  std::string peek() const {
    std::size_t end = at_;
    while (end < text_.size() && !std::isspace(static_cast<unsigned char>(text_[end])) && end - at_ < 20) ++end;
    return text_.substr(at_, end - at_);
  }
  long long line() const {
    long long n = 1;
    for (std::size_t i = 0; i < at_ && i < text_.size(); ++i) n += text_[i] == '\n';
    return n;
  }

  std::string text_, file_;
  std::size_t at_ = 0;
};

void expect(Tokens& t, const std::string& word) {
  const std::string w = t.word();
  if (w != word) t.fail(fmt::format("expected {}, got \"{}\"", word, w.substr(0, 40)));
}

void read_format(Tokens& t) {
  const std::string version = t.word();
  const long long binary = t.integer("the file type");
  t.integer("the data size");
  if (version != "4.1")
    t.fail(fmt::format("MSH version {} (this reader takes 4.1: gmsh -format msh41, or Mesh.MshFileVersion = 4.1)",
                       version));
  if (binary != 0) t.fail("a binary MSH file (this reader takes ASCII: gmsh without -bin, Mesh.Binary = 0)");
  expect(t, "$EndMeshFormat");
}

void read_names(Tokens& t, GmshMesh& m) {
  const long long n = t.integer("the number of physical names");
  for (long long k = 0; k < n; ++k) {
    GmshMesh::PhysicalName p;
    p.dim = static_cast<int>(t.integer("a physical group's dimension"));
    p.tag = static_cast<int>(t.integer("a physical tag"));
    std::string name = t.rest_of_line();
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = name.substr(1, name.size() - 2);
    p.name = name;
    m.names.push_back(p);
  }
  expect(t, "$EndPhysicalNames");
}

/// $Entities: the physical tags of each point, curve, surface and volume.
void read_entities(Tokens& t, GmshMesh& m) {
  long long counts[4];
  for (long long& c : counts) c = t.integer("the number of entities");
  for (int dim = 0; dim < 4; ++dim)
    for (long long k = 0; k < counts[dim]; ++k) {
      const int tag = static_cast<int>(t.integer("an entity tag"));
      for (int c = 0; c < (dim == 0 ? 3 : 6); ++c) t.real("an entity's coordinates or bounding box");
      const long long physicals = t.integer("the number of physical tags");
      std::vector<int>& tags = m.entity_physicals[{dim, tag}];
      for (long long j = 0; j < physicals; ++j) tags.push_back(static_cast<int>(t.integer("a physical tag")));
      if (dim > 0) {
        const long long bounding = t.integer("the number of bounding entities");
        for (long long j = 0; j < bounding; ++j) t.integer("a bounding entity");
      }
    }
  expect(t, "$EndEntities");
}

void read_nodes(Tokens& t, GmshMesh& m, std::unordered_map<long long, int>& index) {
  const long long blocks = t.integer("the number of node blocks");
  const long long total = t.integer("the number of nodes");
  t.integer("the smallest node tag");
  t.integer("the largest node tag");
  m.coordinates.reserve(static_cast<std::size_t>(total));
  index.reserve(static_cast<std::size_t>(total));
  std::vector<long long> tags;
  for (long long b = 0; b < blocks; ++b) {
    const long long dim = t.integer("a node block's entity dimension");
    t.integer("a node block's entity tag");
    const long long parametric = t.integer("whether the nodes are parametric");
    const long long n = t.integer("a node block's number of nodes");
    tags.resize(static_cast<std::size_t>(n));
    for (long long& tag : tags) tag = t.integer("a node tag");
    for (const long long tag : tags) {
      std::array<double, 3> x{t.real("a node's x"), t.real("a node's y"), t.real("a node's z")};
      if (parametric)
        for (long long c = 0; c < std::min<long long>(dim, 3); ++c) t.real("a node's parametric coordinate");
      if (!index.emplace(tag, static_cast<int>(m.coordinates.size())).second)
        t.fail(fmt::format("node {} is defined twice", tag));
      m.coordinates.push_back(x);
    }
  }
  if (static_cast<long long>(m.coordinates.size()) != total)
    t.fail(fmt::format("$Nodes announces {} nodes and holds {}", total, m.coordinates.size()));
  expect(t, "$EndNodes");
}

void read_elements(Tokens& t, GmshMesh& m, const std::unordered_map<long long, int>& index) {
  const long long blocks = t.integer("the number of element blocks");
  t.integer("the number of elements");
  t.integer("the smallest element tag");
  t.integer("the largest element tag");
  for (long long b = 0; b < blocks; ++b) {
    GmshMesh::Block block;
    block.dim = static_cast<int>(t.integer("an element block's entity dimension"));
    block.entity = static_cast<int>(t.integer("an element block's entity tag"));
    block.type = static_cast<int>(t.integer("an element type"));
    const long long n = t.integer("an element block's number of elements");
    block.per = gmsh_nodes_per_element(block.type);
    if (block.per == 0) t.fail(fmt::format("element type {}, which this reader does not know", block.type));
    block.nodes.reserve(static_cast<std::size_t>(n * block.per));
    block.tags.reserve(static_cast<std::size_t>(n));
    for (long long e = 0; e < n; ++e) {
      block.tags.push_back(t.integer("an element tag"));
      for (int a = 0; a < block.per; ++a) {
        const long long tag = t.integer("an element's node tag");
        const auto found = index.find(tag);
        if (found == index.end())
          t.fail(fmt::format("element {} names node {}, which $Nodes does not hold", block.tags.back(), tag));
        block.nodes.push_back(found->second);
      }
    }
    m.blocks.push_back(std::move(block));
  }
  expect(t, "$EndElements");
}

}  // namespace

int gmsh_nodes_per_element(int type) {
  switch (type) {
    case 1: return 2;    // line
    case 2: return 3;    // triangle
    case 3: return 4;    // quadrangle
    case 4: return 4;    // tetrahedron
    case 5: return 8;    // hexahedron
    case 6: return 6;    // prism
    case 7: return 5;    // pyramid
    case 8: return 3;    // second-order line
    case 9: return 6;    // second-order triangle
    case 10: return 9;   // second-order quadrangle
    case 11: return 10;  // second-order tetrahedron
    case 12: return 27;  // second-order hexahedron
    case 15: return 1;   // point
    case 16: return 8;   // serendipity quadrangle
    case 17: return 20;  // serendipity hexahedron
    default: return 0;
  }
}

std::string gmsh_element_name(int type) {
  switch (type) {
    case 1: return "2-node line";
    case 2: return "3-node triangle";
    case 3: return "4-node quadrangle";
    case 4: return "4-node tetrahedron";
    case 5: return "8-node hexahedron";
    case 6: return "6-node prism";
    case 7: return "5-node pyramid";
    case 15: return "point";
    default: return fmt::format("second-order element (gmsh type {})", type);
  }
}

GmshMesh read_gmsh(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the mesh file", file.string()));
  std::ostringstream text;
  text << in.rdbuf();
  Tokens t(text.str(), file.string());
  GmshMesh m;
  m.file = file.string();
  std::unordered_map<long long, int> index;  // node tag -> its place in coordinates
  bool format = false, nodes = false, elements = false;
  while (!t.done()) {
    const std::string section = t.word();
    if (section.empty() || section[0] != '$') t.fail(fmt::format("expected a $Section, got \"{}\"", section.substr(0, 40)));
    if (section == "$MeshFormat") {
      read_format(t);
      format = true;
    } else if (!format) {
      t.fail("expected $MeshFormat first (is this a gmsh MSH file?)");
    } else if (section == "$PhysicalNames") {
      read_names(t, m);
    } else if (section == "$Entities") {
      read_entities(t, m);
    } else if (section == "$Nodes") {
      read_nodes(t, m, index);
      nodes = true;
    } else if (section == "$Elements") {
      if (!nodes) t.fail("$Elements before $Nodes");
      read_elements(t, m, index);
      elements = true;
    } else {  // sections the bodies do not need ($PartitionedEntities, $NodeData, ...)
      t.skip_past("$End" + section.substr(1));
    }
  }
  if (!format) throw InputError(fmt::format("{}: an empty file (expected a gmsh MSH 4.1 mesh)", file.string()));
  if (!nodes || !elements)
    throw InputError(fmt::format("{}: no {} section", file.string(), nodes ? "$Elements" : "$Nodes"));
  return m;
}

}  // namespace gradmpm
