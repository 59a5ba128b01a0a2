// Import of Gmsh .msh files (ASCII, formats 2.2 and 4.1), tetrahedra only.
//
// Linear tetrahedra (element type 4) are read; every other element type is skipped with a
// note. Tets are grouped by physical volume: a group's name comes from $PhysicalNames (or is
// "physical-<tag>"), tets without a physical tag form one unnamed group.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

/// A malformed or unsupported file: the message starts with "FILE:LINE:".
struct GmshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct GmshGroup {
  int physical_tag = 0;   // 0: no physical group
  std::string name;       // "" when unnamed
  std::vector<Tet> tets;  // indices into GmshMesh::x
};

struct GmshMesh {
  std::string path;
  double version = 0.0;
  std::vector<Vec3> x;
  std::vector<GmshGroup> groups;   // sorted by physical tag
  std::vector<std::string> notes;  // skipped element types etc.
};

GmshMesh read_gmsh(const std::string& path);

/// The tets of one named physical group ("" or "*": all tets of the file), unused nodes
/// dropped. Throws GmshError naming the file and the groups available when `group` is absent.
TetMesh gmsh_body(const GmshMesh& mesh, const std::string& group);

}  // namespace tc
