// Surface topology of each body: boundary faces (outward), boundary edges, boundary nodes,
// node→faces adjacency, averaged node normals, edge-length statistics.
#pragma once

#include <array>
#include <vector>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

using Face = std::array<Index, 3>;
using Edge = std::array<Index, 2>;

/// Outward faces of a positively oriented tet (v0, v1, v2, v3): face i is opposite node i and
/// its normal (b - a) × (c - a) points away from that node.
inline constexpr std::array<std::array<int, 3>, 4> k_tet_faces = {
    {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
/// The six edges of a tet as local node pairs.
inline constexpr std::array<std::array<int, 2>, 6> k_tet_edges = {
    {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};

/// One body's surface. All node indices are global (into Mesh::x).
struct Surface {
  Index body = 0;
  std::vector<Face> faces;      // boundary faces, outward normal (b-a)×(c-a)
  std::vector<Index> face_tet;  // the tet each face belongs to
  std::vector<Edge> edges;      // unique boundary edges, e[0] < e[1], sorted
  std::vector<Index> nodes;     // boundary nodes, sorted
  // node→faces adjacency in CSR form over `nodes`: the faces around nodes[i] are
  // node_faces[node_face_offsets[i] .. node_face_offsets[i+1]).
  std::vector<Index> node_face_offsets;
  std::vector<Index> node_faces;
  double mean_edge_length = 0.0;  // over all tet edges of the body (the contact-boundary notes' dx)
  double max_edge_length =
      0.0;  // over all tet edges of the body (the contact-boundary notes' Rmax)
  /// Euler characteristic V - E + F of the surface (2 for a closed sphere-like surface).
  long euler_characteristic() const {
    return static_cast<long>(nodes.size()) - static_cast<long>(edges.size()) +
           static_cast<long>(faces.size());
  }
};

/// The tet across each face of every tet (face i opposite node i, as in k_tet_faces):
/// k_no_tet on the boundary, k_mirror_tet on a symmetry plane (the tet's own mirror image lies
/// across: the face is interior to the whole). Throws MeshError when a face is shared by more
/// than two tets (non-conforming mesh).
using TetNeighbours = std::vector<std::array<Index, 4>>;
inline constexpr Index k_no_tet = -1;
inline constexpr Index k_mirror_tet = -2;
TetNeighbours tet_neighbours(const Mesh& mesh);

/// Builds the surface of every body from the tet connectivity at reference positions.
/// Throws MeshError when a face is shared by more than two tets (non-conforming mesh).
std::vector<Surface> build_surfaces(const Mesh& mesh);

/// The surfaces once the tets marked in `removed` (one flag per tet; empty: none) are gone:
/// every face of a remaining tet with no remaining tet across it, from the adjacency alone
/// (fracture exposes interior faces without anyone declaring them). Edge-length statistics
/// stay those of the whole body.
std::vector<Surface> build_surfaces(const Mesh& mesh, const TetNeighbours& neighbours,
                                    const std::vector<char>& removed);

/// Each body's tet edge lengths at the reference positions, over all its tets' six edges (an
/// interior edge once per tet that holds it): Surface's mean_edge_length and max_edge_length.
struct EdgeLengths {
  double mean = 0.0, max = 0.0;
};
std::vector<EdgeLengths> body_edge_lengths(const Mesh& mesh);

/// The same with the bodies' edge lengths given (they never change: fracture, which builds the
/// surfaces at its first conversion and updates them after each one, computes them once).
std::vector<Surface> build_surfaces(const Mesh& mesh, const TetNeighbours& neighbours,
                                    const std::vector<char>& removed,
                                    const std::vector<EdgeLengths>& lengths);

/// The surfaces once more tets are gone: `surfaces` what build_surfaces gave (one a body, in
/// the bodies' order) before the tets `gone` were removed, `removed` marking them now too. Only
/// the bodies that lost a tet change, and in them only the faces of the lost tets and of their
/// neighbours: the result is build_surfaces' for `removed`, field for field (test
/// `Surface.UpdatedSurfacesAreTheFreshBuild`), without reading every tet. Each tet of `gone` once,
/// none of them removed when `surfaces` were built.
void update_surfaces(const Mesh& mesh, const TetNeighbours& neighbours,
                     const std::vector<char>& removed, const std::vector<Index>& gone,
                     std::vector<Surface>& surfaces);

/// The smallest mean tet edge of the surfaces' bodies (0 when no surface has an edge): the
/// length the binding lists' reach and the contact's separation are fractions of.
double smallest_mean_edge(const std::vector<Surface>& surfaces);

/// Unit normal of a face at positions x (zero vector for a degenerate face).
Vec3 face_normal(const Face& f, const std::vector<Vec3>& x);

/// Averaged normals of the surface nodes at positions x (the contact-boundary notes: the mean of
/// the unit normals of the faces around the node, normalised), one per entry of surface.nodes.
std::vector<Vec3> node_normals(const Surface& surface, const std::vector<Vec3>& x);

/// Number of surface edges not shared by exactly two surface faces (0 for a manifold surface).
Index non_manifold_edges(const Surface& surface);

}  // namespace tc
