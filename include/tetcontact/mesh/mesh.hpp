// Tetrahedral meshes in structure-of-arrays form.
//
// Node positions are an N×3 array (`std::vector<Vec3>`), tetrahedra an M×4 array of node
// indices with positive orientation (det[x1-x0, x2-x0, x3-x0] > 0). Several bodies share one
// Mesh; body b owns the contiguous node range [node_begin, node_end) and tet range
// [tet_begin, tet_end).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace tc {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Index = std::int32_t;
using Tet = std::array<Index, 4>;

/// A mesh error (inverted or degenerate tet, bad topology): the message names the body and tet.
struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One body's tetrahedra before assembly: local node indices.
struct TetMesh {
  std::vector<Vec3> x;
  std::vector<Tet> tets;
};

struct BodyRange {
  std::string name;
  Index node_begin = 0, node_end = 0;
  Index tet_begin = 0, tet_end = 0;
  Index node_count() const { return node_end - node_begin; }
  Index tet_count() const { return tet_end - tet_begin; }
};

/// A symmetry plane x[axis] = at (mesh/symmetry.hpp): the modelled part lies at x[axis] ≥ at.
struct SymmetryPlane {
  int axis = 0;  // 0, 1, 2: x, y, z
  double at = 0.0;
};

struct Mesh {
  std::vector<Vec3> x;            // N×3 reference positions
  std::vector<Tet> tets;          // M×4, positive orientation
  std::vector<BodyRange> bodies;  // per-body ranges
  std::vector<Index> tet_body;    // M: body of each tet
  std::vector<Index> node_body;   // N: body of each node
  /// The planes the bodies were cut along: the mesh is part of a whole mirrored across them
  /// (empty: the mesh is the whole).
  std::vector<SymmetryPlane> symmetry;

  Index node_count() const { return static_cast<Index>(x.size()); }
  Index tet_count() const { return static_cast<Index>(tets.size()); }
};

/// Signed volume of the tetrahedron (a, b, c, d): det[b-a, c-a, d-a] / 6.
inline double tet_signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

/// What orient_tets did.
struct OrientReport {
  bool flipped_all = false;  // the whole body used the opposite (negative) convention
};

/// Enforces positive orientation on one body's tets.
/// A valid tet mesh has every tet of one orientation. If all tets are negative the file uses
/// the opposite convention and every tet is reordered; if the signs are mixed the minority are
/// inverted (folded) elements and a MeshError names the first one. A tet whose |volume| is at
/// most 1e-12 of the body's mean |volume| is degenerate (zero volume) and also rejected.
OrientReport orient_tets(TetMesh& mesh, const std::string& body_name);

/// Appends a body (oriented with orient_tets first) and returns its index.
Index add_body(Mesh& mesh, const std::string& name, TetMesh body);

/// Volume of every tet at positions x.
std::vector<double> tet_volumes(const std::vector<Vec3>& x, const std::vector<Tet>& tets);

/// Total signed volume of a body's tets.
double total_volume(const TetMesh& mesh);

/// Total volume of one body at positions x.
double body_volume(const Mesh& mesh, Index body, const std::vector<Vec3>& x);

/// Drops nodes no tet references and renumbers the rest (import of files that carry
/// geometry points).
void compact_nodes(TetMesh& mesh);

}  // namespace tc
