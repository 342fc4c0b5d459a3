#pragma once
// A gmsh mesh as the MSH 4.1 ASCII file holds it (https://gmsh.info/doc/texinfo/gmsh.html,
// "MSH file format"): the nodes, the element blocks of each geometric entity, the
// entities' physical groups and the groups' names. Read by a small reader of the
// documented format rather than gmsh's own library: the Debian libgmsh-dev brings
// OpenCASCADE, FLTK and more for what is a page of parsing, and the MSH format is stable
// and specified. Only what the bodies need is kept (docs/geometry.md).
#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace gradmpm {

struct GmshMesh {
  struct PhysicalName {
    int dim = 0, tag = 0;
    std::string name;
  };
  /// One $Elements block: `count` elements of one type on one entity, their nodes as
  /// indices into `coordinates` (`per` per element), and their tags.
  struct Block {
    int dim = 0, entity = 0, type = 0, per = 0;
    std::vector<int> nodes;
    std::vector<long long> tags;
    int count() const { return per > 0 ? static_cast<int>(nodes.size()) / per : 0; }
  };

  std::string file;  ///< as given, for messages
  std::vector<std::array<double, 3>> coordinates;
  std::vector<PhysicalName> names;
  /// (entity dimension, entity tag) -> its physical tags ($Entities)
  std::map<std::pair<int, int>, std::vector<int>> entity_physicals;
  std::vector<Block> blocks;
};

/// Reads a MSH 4.1 ASCII file. Throws InputError "FILE: what is wrong" (a binary or
/// older file, a missing section, a node an element names but the file does not hold,
/// a truncated section).
GmshMesh read_gmsh(const std::filesystem::path& file);

/// The number of nodes of a gmsh element type, 0 for a type the reader does not know.
int gmsh_nodes_per_element(int type);
/// Its name in messages ("3-node triangle").
std::string gmsh_element_name(int type);

}  // namespace gradmpm
